-- 0001 (PostgreSQL): the store's key/value metadata and the DEMs with their blocks; the same
-- tables, keys and checks as migrations/sqlite/0001_dems.sql. Column types: SQLite's INTEGER is
-- bigint, REAL double precision, BLOB bytea. Foreign keys are DEFERRABLE INITIALLY DEFERRED,
-- checked at commit (the writers may insert a row before the one it names, as SQLite allows them
-- with its checks turned off: db/sql/unchecked_foreign_keys.h).
--
-- A row inserted without an id gets 1 + the largest id of its table, as SQLite numbers an
-- INTEGER PRIMARY KEY (db/sql/bulk_write.h relies on it); one trigger function per table keeps
-- its query plan cached. Writers hold the store's advisory lock (PgConnection::BeginWrite), so
-- no two compute the same number.
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
  sources    text NOT NULL DEFAULT '[]'
);

CREATE FUNCTION tinbase_dems_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN
    NEW.id := (SELECT coalesce(max(id), 0) + 1 FROM dems);
  END IF;
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
