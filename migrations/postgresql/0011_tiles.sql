-- 0011 (PostgreSQL): the terrain tile pyramids (migrations/sqlite/0011_tiles.sql).
CREATE TABLE tile_pyramids(
  surface    bigint PRIMARY KEY REFERENCES surfaces(id) ON DELETE CASCADE
             DEFERRABLE INITIALLY DEFERRED,
  max_zoom   bigint NOT NULL CHECK (max_zoom BETWEEN 0 AND 24),
  extensions text NOT NULL,
  water_tag  text,
  min_height double precision NOT NULL,
  max_height double precision NOT NULL,
  tx         bigint NOT NULL
);

CREATE TABLE tile_levels(
  surface         bigint NOT NULL REFERENCES tile_pyramids(surface) ON DELETE CASCADE
                  DEFERRABLE INITIALLY DEFERRED,
  level           bigint NOT NULL,
  geometric_error double precision NOT NULL,
  PRIMARY KEY (surface, level)
);

CREATE TABLE tiles(
  surface bigint NOT NULL REFERENCES tile_pyramids(surface) ON DELETE CASCADE
          DEFERRABLE INITIALLY DEFERRED,
  level   bigint NOT NULL,
  x       bigint NOT NULL,
  y       bigint NOT NULL,
  data    bytea NOT NULL,
  tx      bigint NOT NULL,
  PRIMARY KEY (surface, level, x, y)
);
