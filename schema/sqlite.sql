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

CREATE TABLE features(
  id         INTEGER PRIMARY KEY,
  surface    INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  name       TEXT,
  mode       TEXT NOT NULL CHECK (mode IN ('clip', 'erase', 'fill', 'replace', 'breakline')),
  level      REAL,
  tag        INTEGER REFERENCES tags(id),
  attributes TEXT NOT NULL DEFAULT '{}',
  geometry   BLOB NOT NULL,
  min_x      REAL NOT NULL,
  min_y      REAL NOT NULL,
  max_x      REAL NOT NULL,
  max_y      REAL NOT NULL,
  tx         INTEGER NOT NULL
);
CREATE INDEX features_surface ON features(surface);

CREATE TABLE constraints(
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  va      INTEGER NOT NULL,
  vb      INTEGER NOT NULL,
  feature INTEGER REFERENCES features(id) ON DELETE CASCADE,
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

CREATE TABLE tile_pyramids(
  surface    INTEGER PRIMARY KEY REFERENCES surfaces(id) ON DELETE CASCADE,
  max_zoom   INTEGER NOT NULL CHECK (max_zoom BETWEEN 0 AND 24),
  extensions TEXT NOT NULL,
  water_tag  TEXT,
  min_height REAL NOT NULL,
  max_height REAL NOT NULL,
  tx         INTEGER NOT NULL
);

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
