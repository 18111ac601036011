-- 0014 (PostgreSQL): the edit model's new kinds, as migrations/sqlite/0014_line_modes.sql:
-- features.mode also takes 'softline' and 'points', features.z_from ('dem' or 'feature'),
-- constraints.kind ('hard' or 'soft'); the layers show a line's mode and an edge's kind, and a
-- points feature is in no feature layer. PostgreSQL replaces the check alone where SQLite
-- rebuilt the tables; the columns come last in both.
ALTER TABLE features DROP CONSTRAINT features_mode_check;
ALTER TABLE features ADD CONSTRAINT features_mode_check CHECK (mode IN ('clip', 'erase', 'fill',
  'replace', 'breakline', 'softline', 'points'));
ALTER TABLE features ADD COLUMN z_from text NOT NULL DEFAULT 'dem'
  CHECK (z_from IN ('dem', 'feature'));
ALTER TABLE constraints ADD COLUMN kind text NOT NULL DEFAULT 'hard'
  CHECK (kind IN ('hard', 'soft'));

CREATE OR REPLACE VIEW tinbase_constraints AS
SELECT s.name AS surface, k.va, k.vb, k.feature,
  ST_SetSRID(ST_MakeLine(ST_MakePoint(a.x, a.y, a.z), ST_MakePoint(b.x, b.y, b.z)),
             tinbase_srid()) AS geom, k.kind
FROM constraints k
  JOIN surfaces s ON s.id = k.surface
  JOIN vertices a ON a.id = k.va
  JOIN vertices b ON b.id = k.vb;

CREATE OR REPLACE VIEW tinbase_features AS
SELECT f.id AS fid, s.name AS surface, f.name, f.mode, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode IN ('clip', 'erase', 'fill', 'replace');

CREATE OR REPLACE VIEW tinbase_breaklines AS
SELECT f.id AS fid, s.name AS surface, f.name, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom, f.mode
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode IN ('breakline', 'softline');
