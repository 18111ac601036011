-- 0010 (PostgreSQL): the store's rows as PostGIS layers, where SQLite's 0010 made the store a
-- GeoPackage. Each layer is a view over the store's own tables, so it is always in step and no
-- writer does anything for it; QGIS and psql users see the surfaces and the map as layers. The
-- views need PostGIS (CREATE EXTENSION postgis, once per database, by a user allowed to).
-- The layers' SRID: the EPSG code of the store's CRS when it has one, 0 before the first DEM or
-- for a CRS without a code.
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
             tinbase_srid()) AS geom
FROM constraints k
  JOIN surfaces s ON s.id = k.surface
  JOIN vertices a ON a.id = k.va
  JOIN vertices b ON b.id = k.vb;

-- Features keep their WKB: a polygon feature is a MultiPolygon, a breakline a MultiLineString.
CREATE VIEW tinbase_features AS
SELECT f.id AS fid, s.name AS surface, f.name, f.mode, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode <> 'breakline';

CREATE VIEW tinbase_breaklines AS
SELECT f.id AS fid, s.name AS surface, f.name, f.level, g.value AS tag, f.attributes,
  ST_GeomFromWKB(f.geometry, tinbase_srid()) AS geom
FROM features f JOIN surfaces s ON s.id = f.surface LEFT JOIN tags g ON g.id = f.tag
WHERE f.mode = 'breakline';
