-- 0015: every feature keeps its versions (docs/format.md, "Feature versions"). Each edit that adds,
-- updates or removes a feature writes, in its own transaction, one row per feature it touched:
-- the feature as it is after that transaction (present = 1), or as it was when it went
-- (present = 0). Revert, history and export --as-of read the feature's state at any transaction
-- from here. The features already stored get their first version from their own row.
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
INSERT INTO feature_versions(feature, tx, surface, present, name, mode, level, tag, attributes,
                             geometry, min_x, min_y, max_x, max_y, z_from)
SELECT id, tx, surface, 1, name, mode, level, tag, attributes, geometry, min_x, min_y, max_x, max_y,
       z_from
FROM features;
