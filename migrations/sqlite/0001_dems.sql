-- 0001: store metadata and the blocked DEM database.
CREATE TABLE meta(
  key   TEXT PRIMARY KEY,
  value TEXT NOT NULL
) WITHOUT ROWID;

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
);

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
