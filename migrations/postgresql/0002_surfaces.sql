-- 0002 (PostgreSQL): surfaces and their topological tables, features, constraints and the change
-- log; migrations/sqlite/0002_surfaces.sql in PostgreSQL's types (0001 says how).
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
  kind    text NOT NULL CHECK (kind IN ('dem', 'lidar', 'ring', 'steiner', 'user'))
);
CREATE INDEX vertices_surface_xy ON vertices(surface, x, y);

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
  tag     bigint REFERENCES tags(id) DEFERRABLE INITIALLY DEFERRED,
  block   bigint NOT NULL
);
CREATE INDEX triangles_surface_block ON triangles(surface, block);

CREATE TABLE features(
  id         bigint PRIMARY KEY,
  surface    bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE
             DEFERRABLE INITIALLY DEFERRED,
  name       text,
  mode       text NOT NULL CHECK (mode IN ('clip', 'erase', 'fill', 'replace', 'breakline')),
  level      double precision,
  tag        bigint REFERENCES tags(id) DEFERRABLE INITIALLY DEFERRED,
  attributes text NOT NULL DEFAULT '{}',
  geometry   bytea NOT NULL,
  min_x      double precision NOT NULL,
  min_y      double precision NOT NULL,
  max_x      double precision NOT NULL,
  max_y      double precision NOT NULL,
  tx         bigint NOT NULL
);
CREATE INDEX features_surface ON features(surface);

CREATE TABLE constraints(
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  va      bigint NOT NULL,
  vb      bigint NOT NULL,
  feature bigint REFERENCES features(id) ON DELETE CASCADE DEFERRABLE INITIALLY DEFERRED,
  CHECK (va < vb)
);
CREATE INDEX constraints_surface ON constraints(surface, va, vb);

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
  IF NEW.id IS NULL THEN NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM surfaces); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER surfaces_id BEFORE INSERT ON surfaces
  FOR EACH ROW EXECUTE FUNCTION tinbase_surfaces_id();

CREATE FUNCTION tinbase_vertices_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM vertices); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER vertices_id BEFORE INSERT ON vertices
  FOR EACH ROW EXECUTE FUNCTION tinbase_vertices_id();

CREATE FUNCTION tinbase_tags_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM tags); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER tags_id BEFORE INSERT ON tags FOR EACH ROW EXECUTE FUNCTION tinbase_tags_id();

CREATE FUNCTION tinbase_triangles_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM triangles); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER triangles_id BEFORE INSERT ON triangles
  FOR EACH ROW EXECUTE FUNCTION tinbase_triangles_id();

CREATE FUNCTION tinbase_features_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM features); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER features_id BEFORE INSERT ON features
  FOR EACH ROW EXECUTE FUNCTION tinbase_features_id();

CREATE FUNCTION tinbase_changes_tx() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.tx IS NULL THEN NEW.tx := (SELECT coalesce(max(tx), 0) + 1 FROM changes); END IF;
  RETURN NEW;
END $$;
CREATE TRIGGER changes_tx BEFORE INSERT ON changes
  FOR EACH ROW EXECUTE FUNCTION tinbase_changes_tx();
