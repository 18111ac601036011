-- 0015 (PostgreSQL): every feature keeps its versions (as migrations/sqlite/0015_feature_versions.sql).
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
INSERT INTO feature_versions(feature, tx, surface, present, name, mode, level, tag, attributes,
                             geometry, min_x, min_y, max_x, max_y, z_from)
SELECT id, tx, surface, 1, name, mode, level, tag, attributes, geometry, min_x, min_y, max_x, max_y,
       z_from
FROM features;
