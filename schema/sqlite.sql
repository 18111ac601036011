-- The full current tinbase schema for SQLite: what migrations/sqlite/ produce in order.
-- tests/db/migrations_test.cc checks that the two agree exactly.
CREATE TABLE meta(
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
) WITHOUT ROWID;

-- block_col0 and block_row0 were added by 0003 (ALTER TABLE appends to SQLite's text of the
-- table, hence their layout).
CREATE TABLE dems(
  id         INTEGER PRIMARY KEY,
  name       TEXT NOT NULL UNIQUE,
  crs_wkt    TEXT NOT NULL,
  origin_x   REAL NOT NULL,
  origin_y   REAL NOT NULL,
  cell_x     REAL NOT NULL CHECK (cell_x > 0),
  cell_y     REAL NOT NULL CHECK (cell_y < 0),
  width      INTEGER NOT NULL CHECK (width > 0),
  height     INTEGER NOT NULL CHECK (height > 0),
  block_size INTEGER NOT NULL CHECK (block_size > 0),
  nodata     REAL,
  levels     INTEGER NOT NULL DEFAULT 1,
  sources    TEXT NOT NULL DEFAULT '[]'
  , block_col0 INTEGER NOT NULL DEFAULT 0,
  block_row0 INTEGER NOT NULL DEFAULT 0);

CREATE TABLE dem_blocks(
  dem   INTEGER NOT NULL REFERENCES dems(id) ON DELETE CASCADE,
  level INTEGER NOT NULL,
  bx    INTEGER NOT NULL,
  by    INTEGER NOT NULL,
  codec INTEGER NOT NULL,
  data  BLOB NOT NULL,
  zmin  REAL,
  zmax  REAL,
  PRIMARY KEY (dem, level, bx, by)
) WITHOUT ROWID;
CREATE INDEX dem_blocks_extent ON dem_blocks(dem, level, by, bx, zmin, zmax);

CREATE TABLE surfaces(
  id             INTEGER PRIMARY KEY,
  name           TEXT NOT NULL UNIQUE,
  kind           TEXT NOT NULL CHECK (kind IN ('delaunay', 'free')),
  method         TEXT NOT NULL,
  tolerance      REAL,
  dem            INTEGER REFERENCES dems(id),
  block_origin_x REAL NOT NULL,
  block_origin_y REAL NOT NULL,
  block_size     REAL NOT NULL CHECK (block_size > 0),
  created_tx     INTEGER
);

-- Rebuilt by 0007 (kind's CHECK without IN: cheaper per inserted row); the rename that ends the
-- rebuild stores the name quoted.
CREATE TABLE "vertices"(
  id      INTEGER PRIMARY KEY,
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  x       REAL NOT NULL,
  y       REAL NOT NULL,
  z       REAL NOT NULL,
  kind    TEXT NOT NULL CHECK (kind = 'dem' OR kind = 'lidar' OR kind = 'ring' OR
                               kind = 'steiner' OR kind = 'user')
);
CREATE INDEX vertices_surface ON vertices(surface);

CREATE TABLE tags(
  id    INTEGER PRIMARY KEY,
  value TEXT NOT NULL UNIQUE
);

-- tag is an id of tags, not declared a foreign key (0009: SQLite updated a declared key row by
-- row in two passes); `tinbase check` reports one that is not (unknown-tag).
CREATE TABLE "triangles"(
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
CREATE INDEX triangles_surface_block ON triangles(surface, block);

-- Rebuilt by 0014 (mode's CHECK takes 'softline' and 'points'; z_from), with constraints (kind).
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

CREATE TABLE changes(
  tx      INTEGER PRIMARY KEY,
  time    TEXT NOT NULL,
  surface INTEGER,
  feature INTEGER,
  action  TEXT NOT NULL,
  removed INTEGER NOT NULL DEFAULT 0,
  added   INTEGER NOT NULL DEFAULT 0,
  min_x   REAL,
  min_y   REAL,
  max_x   REAL,
  max_y   REAL
);

-- 0010: the store as a GeoPackage (views over the tables above; docs/format.md).
CREATE TABLE tinbase_gpkg_pow2(
  p REAL PRIMARY KEY,  -- 2^e
  e INTEGER NOT NULL
) WITHOUT ROWID;
-- 0010 fills it with every normal power of two.

-- Byte k of b is k.
CREATE VIEW tinbase_gpkg_bytes(b) AS SELECT CAST(
  X'000102030405060708090A0B0C0D0E0F101112131415161718191A1B1C1D1E1F' ||
  X'202122232425262728292A2B2C2D2E2F303132333435363738393A3B3C3D3E3F' ||
  X'404142434445464748494A4B4C4D4E4F505152535455565758595A5B5C5D5E5F' ||
  X'606162636465666768696A6B6C6D6E6F707172737475767778797A7B7C7D7E7F' ||
  X'808182838485868788898A8B8C8D8E8F909192939495969798999A9B9C9D9E9F' ||
  X'A0A1A2A3A4A5A6A7A8A9AAABACADAEAFB0B1B2B3B4B5B6B7B8B9BABBBCBDBEBF' ||
  X'C0C1C2C3C4C5C6C7C8C9CACBCCCDCECFD0D1D2D3D4D5D6D7D8D9DADBDCDDDEDF' ||
  X'E0E1E2E3E4E5E6E7E8E9EAEBECEDEEEFF0F1F2F3F4F5F6F7F8F9FAFBFCFDFEFF' AS BLOB);

-- The 24 bytes of (x, y, z) of every vertex, as little-endian doubles (text; see above).
CREATE VIEW tinbase_gpkg_vertex_xyz(id, xyz) AS
SELECT v.id, (
  SELECT
    substr(b, (wx & 255) + 1, 1) || substr(b, ((wx >> 8) & 255) + 1, 1) ||
    substr(b, ((wx >> 16) & 255) + 1, 1) || substr(b, ((wx >> 24) & 255) + 1, 1) ||
    substr(b, ((wx >> 32) & 255) + 1, 1) || substr(b, ((wx >> 40) & 255) + 1, 1) ||
    substr(b, ((wx >> 48) & 255) + 1, 1) || substr(b, ((wx >> 56) & 255) + 1, 1) ||
    substr(b, (wy & 255) + 1, 1) || substr(b, ((wy >> 8) & 255) + 1, 1) ||
    substr(b, ((wy >> 16) & 255) + 1, 1) || substr(b, ((wy >> 24) & 255) + 1, 1) ||
    substr(b, ((wy >> 32) & 255) + 1, 1) || substr(b, ((wy >> 40) & 255) + 1, 1) ||
    substr(b, ((wy >> 48) & 255) + 1, 1) || substr(b, ((wy >> 56) & 255) + 1, 1) ||
    substr(b, (wz & 255) + 1, 1) || substr(b, ((wz >> 8) & 255) + 1, 1) ||
    substr(b, ((wz >> 16) & 255) + 1, 1) || substr(b, ((wz >> 24) & 255) + 1, 1) ||
    substr(b, ((wz >> 32) & 255) + 1, 1) || substr(b, ((wz >> 40) & 255) + 1, 1) ||
    substr(b, ((wz >> 48) & 255) + 1, 1) || substr(b, ((wz >> 56) & 255) + 1, 1)
  FROM tinbase_gpkg_bytes, (
    SELECT
      CASE WHEN px.p IS NULL THEN 0 ELSE (CASE WHEN v.x < 0 THEN 1 << 63 ELSE 0 END) |
        ((px.e + 1023) << 52) | CAST((abs(v.x) / px.p - 1.0) * 4503599627370496.0 AS INTEGER)
      END AS wx,
      CASE WHEN py.p IS NULL THEN 0 ELSE (CASE WHEN v.y < 0 THEN 1 << 63 ELSE 0 END) |
        ((py.e + 1023) << 52) | CAST((abs(v.y) / py.p - 1.0) * 4503599627370496.0 AS INTEGER)
      END AS wy,
      CASE WHEN pz.p IS NULL THEN 0 ELSE (CASE WHEN v.z < 0 THEN 1 << 63 ELSE 0 END) |
        ((pz.e + 1023) << 52) | CAST((abs(v.z) / pz.p - 1.0) * 4503599627370496.0 AS INTEGER)
      END AS wz
    FROM (SELECT 1)
      LEFT JOIN (SELECT p, e FROM tinbase_gpkg_pow2 WHERE p <= abs(v.x)
                 ORDER BY p DESC LIMIT 1) px
      LEFT JOIN (SELECT p, e FROM tinbase_gpkg_pow2 WHERE p <= abs(v.y)
                 ORDER BY p DESC LIMIT 1) py
      LEFT JOIN (SELECT p, e FROM tinbase_gpkg_pow2 WHERE p <= abs(v.z)
                 ORDER BY p DESC LIMIT 1) pz))
FROM vertices v;

-- The store's CRS as a GeoPackage spatial reference system, and the 8-byte geometry header that
-- names it. srs_id: the EPSG code when the CRS has one, 100000 for another CRS, -1 (undefined
-- cartesian) before the first DEM has set one.
CREATE VIEW tinbase_gpkg_srs(srs_id, srs_name, organization, definition, header) AS
SELECT id, coalesce(label, 'undefined'),
  CASE WHEN label LIKE 'EPSG:%' THEN 'EPSG' ELSE 'NONE' END, coalesce(wkt, 'undefined'),
  CAST(X'47500001' || (SELECT substr(b, (id & 255) + 1, 1) || substr(b, ((id >> 8) & 255) + 1, 1) ||
                              substr(b, ((id >> 16) & 255) + 1, 1) ||
                              substr(b, ((id >> 24) & 255) + 1, 1)
                       FROM tinbase_gpkg_bytes) AS BLOB)
FROM (SELECT CASE WHEN label LIKE 'EPSG:%' THEN CAST(substr(label, 6) AS INTEGER)
                  WHEN wkt IS NULL THEN -1 ELSE 100000 END AS id, label, wkt
      FROM (SELECT (SELECT value FROM meta WHERE key = 'crs_label') AS label,
                   (SELECT value FROM meta WHERE key = 'crs_wkt') AS wkt));

CREATE VIEW gpkg_spatial_ref_sys(srs_name, srs_id, organization, organization_coordsys_id,
                                 definition, description) AS
SELECT 'Undefined cartesian SRS', -1, 'NONE', -1, 'undefined',
  'undefined cartesian coordinate reference system'
UNION ALL
SELECT 'Undefined geographic SRS', 0, 'NONE', 0, 'undefined',
  'undefined geographic coordinate reference system'
UNION ALL
SELECT 'WGS 84 geodetic', 4326, 'EPSG', 4326,
  'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",' ||
  '6378137,298.257223563,AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],' ||
  'PRIMEM["Greenwich",0,' ||
  'AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],' ||
  'AXIS["Latitude",NORTH],AXIS["Longitude",EAST],AUTHORITY["EPSG","4326"]]',
  'longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid'
UNION ALL
SELECT srs_name, srs_id, organization, srs_id, definition, 'the CRS of the tinbase store'
FROM tinbase_gpkg_srs WHERE srs_id NOT IN (-1, 0, 4326);

-- GDAL takes a view column for the geometry (and the layer's CRS) only when SQLite reports a
-- geometry type name as the column's declared type. Only a table column carries one, and a
-- compound SELECT takes its column types from its first arm, so each layer is an empty table
-- that declares its columns, UNION ALL the rows. The second arm has no WHERE and no join (every
-- lookup is a subquery), so SQLite counts a layer as the rows of its table (its count-of-view
-- optimisation) instead of building every geometry, and a FID filter reaches the table's key.
CREATE TABLE tinbase_gpkg_vertices_columns(fid INTEGER, surface TEXT, kind TEXT, geom POINT);
CREATE VIEW tinbase_vertices AS
SELECT * FROM tinbase_gpkg_vertices_columns
UNION ALL
SELECT v.id, (SELECT name FROM surfaces WHERE id = v.surface), v.kind,
  CAST((SELECT header FROM tinbase_gpkg_srs) || X'01E9030000' ||
       (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = v.id) AS BLOB)
FROM vertices v;

-- The closing corner repeats the first; the LIMIT keeps SQLite from building its bytes twice.
CREATE TABLE tinbase_gpkg_triangles_columns(fid INTEGER, surface TEXT, v0 INTEGER, v1 INTEGER,
  v2 INTEGER, n0 INTEGER, n1 INTEGER, n2 INTEGER, visible INTEGER, tag TEXT, geom POLYGON);
CREATE VIEW tinbase_triangles AS
SELECT * FROM tinbase_gpkg_triangles_columns
UNION ALL
SELECT t.id, (SELECT name FROM surfaces WHERE id = t.surface), t.v0, t.v1, t.v2, t.n0, t.n1,
  t.n2, t.visible, (SELECT value FROM tags WHERE id = t.tag),
  (SELECT CAST(h || X'01EB0300000100000004000000' || pa || pb || pc || pa AS BLOB)
   FROM (SELECT (SELECT header FROM tinbase_gpkg_srs) AS h,
                (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = t.v0) AS pa,
                (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = t.v1) AS pb,
                (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = t.v2) AS pc
         LIMIT 1))
FROM triangles t;

CREATE TABLE tinbase_gpkg_constraints_columns(fid INTEGER, surface TEXT, va INTEGER, vb INTEGER,
  feature INTEGER, geom LINESTRING, kind TEXT);
CREATE VIEW tinbase_constraints AS
SELECT * FROM tinbase_gpkg_constraints_columns
UNION ALL
SELECT k.rowid, (SELECT name FROM surfaces WHERE id = k.surface), k.va, k.vb, k.feature,
  CAST((SELECT header FROM tinbase_gpkg_srs) || X'01EA03000002000000' ||
       (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = k.va) ||
       (SELECT xyz FROM tinbase_gpkg_vertex_xyz WHERE id = k.vb) AS BLOB), k.kind
FROM constraints k;

-- Features keep their WKB: a polygon feature is a MultiPolygon, a breakline or softline a
-- MultiLineString. 0014 appended each line's mode and each constraint's kind to the layers.
CREATE TABLE tinbase_gpkg_features_columns(fid INTEGER, surface TEXT, name TEXT, mode TEXT,
  level REAL, tag TEXT, attributes TEXT, geom MULTIPOLYGON);
CREATE VIEW tinbase_features AS
SELECT * FROM tinbase_gpkg_features_columns
UNION ALL
SELECT f.id, (SELECT name FROM surfaces WHERE id = f.surface), f.name, f.mode, f.level,
  (SELECT value FROM tags WHERE id = f.tag), f.attributes,
  CAST((SELECT header FROM tinbase_gpkg_srs) || f.geometry AS BLOB)
FROM features f WHERE f.mode IN ('clip', 'erase', 'fill', 'replace');

CREATE TABLE tinbase_gpkg_breaklines_columns(fid INTEGER, surface TEXT, name TEXT, level REAL,
  tag TEXT, attributes TEXT, geom MULTILINESTRING, mode TEXT);
CREATE VIEW tinbase_breaklines AS
SELECT * FROM tinbase_gpkg_breaklines_columns
UNION ALL
SELECT f.id, (SELECT name FROM surfaces WHERE id = f.surface), f.name, f.level,
  (SELECT value FROM tags WHERE id = f.tag), f.attributes,
  CAST((SELECT header FROM tinbase_gpkg_srs) || f.geometry AS BLOB), f.mode
FROM features f WHERE f.mode IN ('breakline', 'softline');

-- GDAL tells 64-bit FIDs from a layer's sqlite_sequence row and, finding none, computes
-- MAX(fid) over the layer: every geometry built once, on every opening. The layers' rows say
-- "64-bit" (store ids are) at no cost. The table exists only to make SQLite create
-- sqlite_sequence, whose rows SQLite lets anyone write.
CREATE TABLE tinbase_gpkg_sequence(id INTEGER PRIMARY KEY AUTOINCREMENT);
-- 0010 gives each layer a row of sqlite_sequence.

-- The surfaces table is registered as an attribute layer: with one, GDAL lists only what
-- gpkg_contents names (its LIST_ALL_TABLES=AUTO), not every internal table.
-- Extents: one scan of the vertices for the mesh layers, the features' stored boxes for theirs.
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

CREATE VIEW gpkg_geometry_columns(table_name, column_name, geometry_type_name, srs_id, z, m) AS
SELECT table_name, 'geom', geometry_type_name, (SELECT srs_id FROM tinbase_gpkg_srs), z, 0
FROM (SELECT 'tinbase_triangles' AS table_name, 'POLYGON' AS geometry_type_name, 1 AS z
      UNION ALL SELECT 'tinbase_vertices', 'POINT', 1
      UNION ALL SELECT 'tinbase_constraints', 'LINESTRING', 1
      UNION ALL SELECT 'tinbase_features', 'MULTIPOLYGON', 0
      UNION ALL SELECT 'tinbase_breaklines', 'MULTILINESTRING', 0);
-- min_vertex and max_vertex were added by 0012.
CREATE TABLE tile_pyramids(
  surface    INTEGER PRIMARY KEY REFERENCES surfaces(id) ON DELETE CASCADE,
  max_zoom   INTEGER NOT NULL CHECK (max_zoom BETWEEN 0 AND 24),
  extensions TEXT NOT NULL,
  water_tag  TEXT,
  min_height REAL NOT NULL,
  max_height REAL NOT NULL,
  tx         INTEGER NOT NULL
, min_vertex INTEGER, max_vertex INTEGER);

CREATE TABLE tile_levels(
  surface         INTEGER NOT NULL REFERENCES tile_pyramids(surface) ON DELETE CASCADE,
  level           INTEGER NOT NULL,
  geometric_error REAL NOT NULL,
  PRIMARY KEY (surface, level)
) WITHOUT ROWID;

CREATE TABLE tiles(
  surface INTEGER NOT NULL REFERENCES tile_pyramids(surface) ON DELETE CASCADE,
  level   INTEGER NOT NULL,
  x       INTEGER NOT NULL,
  y       INTEGER NOT NULL,
  data    BLOB NOT NULL,
  tx      INTEGER NOT NULL,
  PRIMARY KEY (surface, level, x, y)
) WITHOUT ROWID;

-- 0013 adds no table: the header's application_id becomes 0x47503131 (GeoPackage 1.1's
-- 'GP11') and meta gets the row (application, tinbase), by which tinbase knows its stores
-- (docs/format.md).

-- 0015: the versions of every feature (docs/format.md, "Feature versions").
CREATE TABLE feature_versions(
  feature    INTEGER NOT NULL,
  tx         INTEGER NOT NULL,
  surface    INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  present    INTEGER NOT NULL CHECK (present IN (0, 1)),
  name       TEXT,
  mode       TEXT NOT NULL,
  level      REAL,
  tag        INTEGER REFERENCES tags(id),
  attributes TEXT NOT NULL DEFAULT '{}',
  geometry   BLOB NOT NULL,
  min_x      REAL NOT NULL,
  min_y      REAL NOT NULL,
  max_x      REAL NOT NULL,
  max_y      REAL NOT NULL,
  z_from     TEXT NOT NULL DEFAULT 'dem',
  PRIMARY KEY (feature, tx)
) WITHOUT ROWID;
CREATE INDEX feature_versions_tx ON feature_versions(tx);

CREATE TABLE mesh_images(
  tx      INTEGER PRIMARY KEY,
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  image   BLOB NOT NULL
);
