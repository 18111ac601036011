-- 0009: triangles.tag is no longer declared a foreign key of tags(id). With the key declared,
-- SQLite runs an UPDATE of the tag in two passes (the rowids first, then one lookup per row)
-- and looks the parent tag up for every row: a polygon's fill repaints thousands of triangles.
-- Turning enforcement off around those statements (sqlite3_db_config) instead made SQLite
-- expire every prepared statement of the connection, twice an edit, so each was compiled again.
-- The tags an engine writes are interned in the same transaction, tags are never deleted, and
-- `tinbase check` reports a triangle whose tag is not a row of tags (unknown-tag).
-- SQLite cannot drop a constraint, so the table is rebuilt and renamed (no table refers to
-- triangles by foreign key); the rename stores the name quoted, as schema/sqlite.sql shows.
CREATE TABLE triangles_0009(
  id      INTEGER PRIMARY KEY,
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  v0      INTEGER NOT NULL,
  v1      INTEGER NOT NULL,
  v2      INTEGER NOT NULL,
  n0      INTEGER,
  n1      INTEGER,
  n2      INTEGER,
  visible INTEGER NOT NULL DEFAULT 1 CHECK (visible IN (0, 1)),
  tag     INTEGER,
  block   INTEGER NOT NULL
);
INSERT INTO triangles_0009(id, surface, v0, v1, v2, n0, n1, n2, visible, tag, block)
  SELECT id, surface, v0, v1, v2, n0, n1, n2, visible, tag, block FROM triangles;
DROP TABLE triangles;
ALTER TABLE triangles_0009 RENAME TO triangles;
CREATE INDEX triangles_surface_block ON triangles(surface, block);
