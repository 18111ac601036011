-- 0016 (PostgreSQL): the before-image of each edit's mesh rows (as
-- migrations/sqlite/0016_mesh_images.sql).
CREATE TABLE mesh_images(
  tx      bigint PRIMARY KEY,
  surface bigint NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE
          DEFERRABLE INITIALLY DEFERRED,
  image   bytea NOT NULL
);
