-- The full current tinbase schema for PostgreSQL: what migrations/postgresql/ produce in order
-- (the store's schema is the search_path's first). tests/db/postgres/pg_schema_test.cc checks
-- that the two agree exactly: tables, columns, keys, checks, indexes, triggers and views.
CREATE TABLE tinbase_store(application_id integer NOT NULL, schema_version integer NOT NULL);

CREATE TABLE meta(
  key   text PRIMARY KEY,
  value text NOT NULL
);

CREATE TABLE dems(
  id         bigint PRIMARY KEY,
  name       text NOT NULL UNIQUE,
  crs_wkt    text NOT NULL,
  origin_x   double precision NOT NULL,
  origin_y   double precision NOT NULL,
  cell_x     double precision NOT NULL CHECK (cell_x > 0),
  cell_y     double precision NOT NULL CHECK (cell_y < 0),
  width      bigint NOT NULL CHECK (width > 0),
  height     bigint NOT NULL CHECK (height > 0),
  block_size bigint NOT NULL CHECK (block_size > 0),
  nodata     double precision,
  levels     bigint NOT NULL DEFAULT 1,
  sources    text NOT NULL DEFAULT '[]',
  block_col0 bigint NOT NULL DEFAULT 0,
  block_row0 bigint NOT NULL DEFAULT 0
);

-- 0017: ids and change numbers from sequences (concurrent writers, docs/scaling.md).
CREATE SEQUENCE dems_id_seq;
CREATE SEQUENCE surfaces_id_seq;
CREATE SEQUENCE vertices_id_seq;
CREATE SEQUENCE tags_id_seq;
CREATE SEQUENCE triangles_id_seq;
CREATE SEQUENCE features_id_seq;
CREATE SEQUENCE changes_tx_seq;

CREATE FUNCTION tinbase_dems_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('dems_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER dems_id BEFORE INSERT ON dems FOR EACH ROW EXECUTE FUNCTION tinbase_dems_id();

CREATE TABLE dem_blocks(
  dem   bigint NOT NULL REFERENCES dems(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  level bigint NOT NULL,
  bx    bigint NOT NULL,
  "by"  bigint NOT NULL,
  codec bigint NOT NULL,
  data  bytea NOT NULL,
  zmin  double precision,
  zmax  double precision,
  PRIMARY KEY (dem, level, bx, "by")
);
CREATE INDEX dem_blocks_extent ON dem_blocks(dem, level, "by", bx, zmin, zmax);

CREATE TABLE surfaces(
  id             bigint PRIMARY KEY,
  name           text NOT NULL UNIQUE,
  kind           text NOT NULL CHECK (kind IN ('delaunay', 'free')),
  method         text NOT NULL,
  tolerance      double precision,
  dem            bigint REFERENCES dems(id) DEFERRABLE INITIALLY DEFERRED,
  block_origin_x double precision NOT NULL,
  block_origin_y double precision NOT NULL,
  block_size     double precision NOT NULL CHECK (block_size > 0),
  created_tx     bigint
);

CREATE TABLE vertices(
  id      bigint PRIMARY KEY,
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  x       double precision NOT NULL,
  y       double precision NOT NULL,
  z       double precision NOT NULL,
  kind    text NOT NULL CHECK (kind = 'dem' OR kind = 'lidar' OR kind = 'ring' OR
                               kind = 'steiner' OR kind = 'user')
);
CREATE INDEX vertices_surface ON vertices(surface);

CREATE TABLE tags(
  id    bigint PRIMARY KEY,
  value text NOT NULL UNIQUE
);

CREATE TABLE triangles(
  id      bigint PRIMARY KEY,
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  v0      bigint NOT NULL,
  v1      bigint NOT NULL,
  v2      bigint NOT NULL,
  n0      bigint,
  n1      bigint,
  n2      bigint,
  visible bigint NOT NULL DEFAULT 1 CHECK (visible IN (0, 1)),
  tag     bigint,
  block   bigint NOT NULL
);
CREATE INDEX triangles_surface_block ON triangles(surface, block);

CREATE TABLE features(
  id         bigint PRIMARY KEY,
  surface    bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE
             DEFERRABLE INITIALLY DEFERRED,
  name       text,
  mode       text NOT NULL CHECK (mode IN ('clip', 'erase', 'fill', 'replace', 'breakline',
                                           'softline', 'points')),
  level      double precision,
  tag        bigint REFERENCES tags(id) DEFERRABLE INITIALLY DEFERRED,
  attributes text NOT NULL DEFAULT '{}',
  geometry   bytea NOT NULL,
  min_x      double precision NOT NULL,
  min_y      double precision NOT NULL,
  max_x      double precision NOT NULL,
  max_y      double precision NOT NULL,
  tx         bigint NOT NULL,
  z_from     text NOT NULL DEFAULT 'dem' CHECK (z_from IN ('dem', 'feature'))
);
CREATE INDEX features_surface ON features(surface);

CREATE TABLE constraints(
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  va      bigint NOT NULL,
  vb      bigint NOT NULL,
  feature bigint REFERENCES features(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  kind    text NOT NULL DEFAULT 'hard' CHECK (kind IN ('hard', 'soft')),
  CHECK (va < vb)
);
CREATE INDEX constraints_surface ON constraints(surface, va, vb);
CREATE INDEX constraints_feature ON constraints(feature);

CREATE TABLE changes(
  tx      bigint PRIMARY KEY,
  time    text NOT NULL,
  surface bigint,
  feature bigint,
  action  text NOT NULL,
  removed bigint NOT NULL DEFAULT 0,
  added   bigint NOT NULL DEFAULT 0,
  min_x   double precision,
  min_y   double precision,
  max_x   double precision,
  max_y   double precision
);

CREATE FUNCTION tinbase_surfaces_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('surfaces_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER surfaces_id BEFORE INSERT ON surfaces
  FOR EACH ROW EXECUTE FUNCTION tinbase_surfaces_id();

CREATE FUNCTION tinbase_vertices_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('vertices_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER vertices_id BEFORE INSERT ON vertices
  FOR EACH ROW EXECUTE FUNCTION tinbase_vertices_id();

CREATE FUNCTION tinbase_tags_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('tags_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER tags_id BEFORE INSERT ON tags FOR EACH ROW EXECUTE FUNCTION tinbase_tags_id();

CREATE FUNCTION tinbase_triangles_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('triangles_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER triangles_id BEFORE INSERT ON triangles
  FOR EACH ROW EXECUTE FUNCTION tinbase_triangles_id();

CREATE FUNCTION tinbase_features_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('features_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER features_id BEFORE INSERT ON features
  FOR EACH ROW EXECUTE FUNCTION tinbase_features_id();

CREATE FUNCTION tinbase_changes_tx() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.tx IS NULL THEN NEW.tx := nextval('changes_tx_seq'); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER changes_tx BEFORE INSERT ON changes
  FOR EACH ROW EXECUTE FUNCTION tinbase_changes_tx();

DO $$
BEGIN
  IF NOT EXISTS (SELECT 1 FROM pg_extension WHERE extname = 'postgis') THEN
    RAISE EXCEPTION 'PostGIS is not installed in this database: run CREATE EXTENSION postgis '
                    'as a user allowed to (Debian: postgresql-15-postgis-3)';
  END IF;
END $$;

CREATE FUNCTION tinbase_srid() RETURNS integer LANGUAGE sql STABLE AS $$
  SELECT coalesce((SELECT substr(value, 6)::integer FROM meta
                   WHERE key = 'crs_label' AND value ~ '^EPSG:[0-9]+$'), 0)
$$;

CREATE VIEW tinbase_vertices AS
SELECT v.id AS fid, s.name AS surface, v.kind,
  ST_SetSRID(ST_MakePoint(v.x, v.y, v.z), tinbase_srid()) AS geom
FROM vertices v JOIN surfaces s ON s.id = v.surface;

CREATE VIEW tinbase_triangles AS
SELECT t.id AS fid, s.name AS surface, t.v0, t.v1, t.v2, t.n0, t.n1, t.n2, t.visible,
  g.value AS tag,
  ST_SetSRID(ST_MakePolygon(ST_MakeLine(ARRAY[
    ST_MakePoint(a.x, a.y, a.z), ST_MakePoint(b.x, b.y, b.z), ST_MakePoint(c.x, c.y, c.z),
    ST_MakePoint(a.x, a.y, a.z)])), tinbase_srid()) AS geom
FROM triangles t
  JOIN surfaces s ON s.id = t.surface
  JOIN vertices a ON a.id = t.v0
  JOIN vertices b ON b.id = t.v1
  JOIN vertices c ON c.id = t.v2
  LEFT JOIN tags g ON g.id = t.tag;

CREATE VIEW tinbase_constraints AS
SELECT s.name AS surface, k.va, k.vb, k.feature,
  ST_SetSRID(ST_MakeLine(ST_MakePoint(a.x, a.y, a.z), ST_MakePoint(b.x, b.y, b.z)),
             tinbase_srid()) AS geom, k.kind
FROM constraints k
  JOIN surfaces s ON s.id = k.surface
  JOIN vertices a ON a.id = k.va
  JOIN vertices b ON b.id = k.vb;

CREATE VIEW tinbase_features AS
SELECT f.id AS fid, s.name AS surface, f.name, f.mode, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode IN ('clip', 'erase', 'fill', 'replace');

CREATE VIEW tinbase_breaklines AS
SELECT f.id AS fid, s.name AS surface, f.name, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom, f.mode
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode IN ('breakline', 'softline');

CREATE TABLE tile_pyramids(
  surface    bigint PRIMARY KEY REFERENCES surfaces(id) ON DELETE CASCADE
             DEFERRABLE INITIALLY DEFERRED,
  max_zoom   bigint NOT NULL CHECK (max_zoom BETWEEN 0 AND 24),
  extensions text NOT NULL,
  water_tag  text,
  min_height double precision NOT NULL,
  max_height double precision NOT NULL,
  tx         bigint NOT NULL,
  min_vertex bigint,
  max_vertex bigint
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

-- 0015: the versions of every feature (docs/format.md, "Feature versions").
CREATE TABLE feature_versions(
  feature    bigint NOT NULL,
  tx         bigint NOT NULL,
  surface    bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE
             DEFERRABLE INITIALLY DEFERRED,
  present    bigint NOT NULL CHECK (present IN (0, 1)),
  name       text,
  mode       text NOT NULL,
  level      double precision,
  tag        bigint REFERENCES tags(id) DEFERRABLE INITIALLY DEFERRED,
  attributes text NOT NULL DEFAULT '{}',
  geometry   bytea NOT NULL,
  min_x      double precision NOT NULL,
  min_y      double precision NOT NULL,
  max_x      double precision NOT NULL,
  max_y      double precision NOT NULL,
  z_from     text NOT NULL DEFAULT 'dem',
  PRIMARY KEY (feature, tx)
);
CREATE INDEX feature_versions_tx ON feature_versions(tx);

CREATE TABLE mesh_images(
  tx      bigint PRIMARY KEY,
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE
          DEFERRABLE INITIALLY DEFERRED,
  image   bytea NOT NULL
);

-- 0017: a run of n consecutive numbers of a sequence (PgConnection::ReserveIds).
CREATE FUNCTION tinbase_reserve_ids(seq regclass, n bigint) RETURNS bigint LANGUAGE plpgsql AS $$
DECLARE
  first bigint;
BEGIN
  IF n < 1 THEN
    RAISE EXCEPTION 'tinbase_reserve_ids: % numbers asked for, at least 1 expected', n;
  END IF;
  PERFORM pg_advisory_lock(1953063522, seq::oid::integer);
  BEGIN
    first := nextval(seq);
    IF n > 1 THEN PERFORM setval(seq, first + n - 1); END IF;
  EXCEPTION WHEN OTHERS THEN
    PERFORM pg_advisory_unlock(1953063522, seq::oid::integer);
    RAISE;
  END;
  PERFORM pg_advisory_unlock(1953063522, seq::oid::integer);
  RETURN first;
END $$;
