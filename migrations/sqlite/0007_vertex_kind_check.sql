-- 0007: vertices.kind is checked by a chain of comparisons instead of IN (...). The accepted
-- names are the same; SQLite evaluated the five-name IN list by building a temporary b-tree of
-- the names for every row inserted, about half the cost of a vertex row in a bulk import.
-- SQLite cannot alter a CHECK, so the table is rebuilt and renamed (no table refers to vertices
-- by foreign key); the rename stores the name quoted, as schema/sqlite.sql shows.
CREATE TABLE vertices_0007(
  id      INTEGER PRIMARY KEY,
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  x       REAL NOT NULL,
  y       REAL NOT NULL,
  z       REAL NOT NULL,
  kind    TEXT NOT NULL CHECK (kind = 'dem' OR kind = 'lidar' OR kind = 'ring' OR
                               kind = 'steiner' OR kind = 'user')
);
INSERT INTO vertices_0007(id, surface, x, y, z, kind) SELECT id, surface, x, y, z, kind FROM vertices;
DROP TABLE vertices;
ALTER TABLE vertices_0007 RENAME TO vertices;
CREATE INDEX vertices_surface_xy ON vertices(surface, x, y);
