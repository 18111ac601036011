-- 0014: the edit model's new kinds (docs/design.md, "Soft lines and z from the feature").
--  * features.mode also takes 'softline' (a line whose segments are edges for shape only: no
--    hard-breakline rules in exports or slope breaks) and 'points' (surveyed mass points kept as
--    one MultiPoint Z feature).
--  * features.z_from: 'dem' (a line is draped on the surface, as before) or 'feature' (a 3D
--    line keeps its own z).
--  * constraints.kind: 'hard' (a breakline's segment, as before) or 'soft' (a softline's).
-- SQLite cannot alter a CHECK, so features is rebuilt. constraints refers to it with ON DELETE
-- CASCADE, and dropping features would delete every constraint row through it; so both tables
-- are copied aside, dropped (constraints first, so nothing cascades), created again under their
-- own names (no rename: the GeoPackage views of 0010 read both by name) and filled back, with
-- every id and every constraint's rowid (the fid of the tinbase_constraints layer) kept.
CREATE TABLE features_0014 AS SELECT * FROM features;
CREATE TABLE constraints_0014 AS SELECT rowid AS rowid_0014, * FROM constraints;
DROP TABLE constraints;
DROP TABLE features;

CREATE TABLE features(
  id         INTEGER PRIMARY KEY,
  surface    INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  name       TEXT,
  mode       TEXT NOT NULL CHECK (mode IN ('clip', 'erase', 'fill', 'replace', 'breakline',
                                           'softline', 'points')),
  level      REAL,
  tag        INTEGER REFERENCES tags(id),
  attributes TEXT NOT NULL DEFAULT '{}',
  geometry   BLOB NOT NULL,
  min_x      REAL NOT NULL,
  min_y      REAL NOT NULL,
  max_x      REAL NOT NULL,
  max_y      REAL NOT NULL,
  tx         INTEGER NOT NULL,
  z_from     TEXT NOT NULL DEFAULT 'dem' CHECK (z_from IN ('dem', 'feature'))
);
CREATE INDEX features_surface ON features(surface);

CREATE TABLE constraints(
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  va      INTEGER NOT NULL,
  vb      INTEGER NOT NULL,
  feature INTEGER REFERENCES features(id) ON DELETE CASCADE,
  kind    TEXT NOT NULL DEFAULT 'hard' CHECK (kind IN ('hard', 'soft')),
  CHECK (va < vb)
);
CREATE INDEX constraints_surface ON constraints(surface, va, vb);
CREATE INDEX constraints_feature ON constraints(feature);

INSERT INTO features(id, surface, name, mode, level, tag, attributes, geometry, min_x, min_y,
                     max_x, max_y, tx)
  SELECT id, surface, name, mode, level, tag, attributes, geometry, min_x, min_y, max_x, max_y, tx
  FROM features_0014 ORDER BY id;
INSERT INTO constraints(rowid, surface, va, vb, feature)
  SELECT rowid_0014, surface, va, vb, feature FROM constraints_0014 ORDER BY rowid_0014;
DROP TABLE constraints_0014;
DROP TABLE features_0014;

-- The GeoPackage layers: tinbase_features holds the polygon features, tinbase_breaklines the
-- lines of both kinds with their mode, tinbase_constraints each edge's kind. A points feature is
-- in no feature layer (its points are vertices of the tinbase_vertices layer).
ALTER TABLE tinbase_gpkg_constraints_columns ADD COLUMN kind TEXT;
DROP VIEW tinbase_constraints;
CREATE VIEW tinbase_constraints AS
SELECT * FROM tinbase_gpkg_constraints_columns
UNION ALL
SELECT k.rowid, (SELECT name FROM surfaces WHERE id = k.surface), k.va, k.vb, k.feature,
  CAST((SELECT header FROM tinbase_gpkg_srs) || X'01EA03000002000000' ||
       (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = k.va) ||
       (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = k.vb) AS BLOB), k.kind
FROM constraints k;

DROP VIEW tinbase_features;
CREATE VIEW tinbase_features AS
SELECT * FROM tinbase_gpkg_features_columns
UNION ALL
SELECT f.id, (SELECT name FROM surfaces WHERE id = f.surface), f.name, f.mode, f.level,
  (SELECT value FROM tags WHERE id = f.tag), f.attributes,
  CAST((SELECT header FROM tinbase_gpkg_srs) || f.geometry AS BLOB)
FROM features f WHERE f.mode IN ('clip', 'erase', 'fill', 'replace');

ALTER TABLE tinbase_gpkg_breaklines_columns ADD COLUMN mode TEXT;
DROP VIEW tinbase_breaklines;
CREATE VIEW tinbase_breaklines AS
SELECT * FROM tinbase_gpkg_breaklines_columns
UNION ALL
SELECT f.id, (SELECT name FROM surfaces WHERE id = f.surface), f.name, f.level,
  (SELECT value FROM tags WHERE id = f.tag), f.attributes,
  CAST((SELECT header FROM tinbase_gpkg_srs) || f.geometry AS BLOB), f.mode
FROM features f WHERE f.mode IN ('breakline', 'softline');

-- The features' boxes: a points feature is in neither feature layer.
DROP VIEW gpkg_contents;
CREATE VIEW gpkg_contents(table_name, data_type, identifier, description, last_change, min_x,
                          min_y, max_x, max_y, srs_id) AS
WITH mesh(min_x, min_y, max_x, max_y) AS (
  SELECT min(x), min(y), max(x), max(y) FROM vertices),
boxes(breakline, min_x, min_y, max_x, max_y) AS (
  SELECT mode IN ('breakline', 'softline'), min(min_x), min(min_y), max(max_x), max(max_y)
  FROM features WHERE mode <> 'points' GROUP BY mode IN ('breakline', 'softline')),
layers(table_name, data_type, description, breakline) AS (
  SELECT 'tinbase_triangles', 'features', 'the triangles of every surface', NULL
  UNION ALL SELECT 'tinbase_vertices', 'features', 'the vertices of every surface', NULL
  UNION ALL SELECT 'tinbase_constraints', 'features', 'the constrained edges of every surface', NULL
  UNION ALL SELECT 'tinbase_features', 'features', 'the polygon features of every surface', 0
  UNION ALL SELECT 'tinbase_breaklines', 'features', 'the breakline features of every surface', 1
  UNION ALL SELECT 'surfaces', 'attributes', 'the surfaces of the store', NULL)
SELECT l.table_name, l.data_type, l.table_name, l.description,
  coalesce(strftime('%Y-%m-%dT%H:%M:%fZ', (SELECT max(time) FROM changes)),
           '1970-01-01T00:00:00.000Z'),
  CASE WHEN l.data_type = 'attributes' THEN NULL
       WHEN l.breakline IS NULL THEN m.min_x ELSE b.min_x END,
  CASE WHEN l.data_type = 'attributes' THEN NULL
       WHEN l.breakline IS NULL THEN m.min_y ELSE b.min_y END,
  CASE WHEN l.data_type = 'attributes' THEN NULL
       WHEN l.breakline IS NULL THEN m.max_x ELSE b.max_x END,
  CASE WHEN l.data_type = 'attributes' THEN NULL
       WHEN l.breakline IS NULL THEN m.max_y ELSE b.max_y END,
  CASE WHEN l.data_type = 'features' THEN (SELECT srs_id FROM tinbase_gpkg_srs) END
FROM layers l CROSS JOIN mesh m LEFT JOIN boxes b ON b.breakline = l.breakline;
