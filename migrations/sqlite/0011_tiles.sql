-- 0011: terrain tiles kept in the store (docs/tiles.md): one pyramid per surface, its levels,
-- and the quantized-mesh tiles themselves, each with the transaction whose state it shows.
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
