-- 0013: the store opens as a GeoPackage under its own file name, with no "GPKG:" prefix. GDAL's
-- GeoPackage driver takes an SQLite file whose application_id names a GeoPackage; of those ids,
-- 'GP11' (0x47503131, GeoPackage 1.1) asks nothing of user_version, which GeoPackage 1.2 made
-- the spec version (10200 and up), so tinbase keeps its schema version there. The layers are the
-- views of 0010. tinbase knows its own stores by meta's application row from here on (before
-- this migration: by application_id 'TINB'); docs/format.md, "The store as a GeoPackage".
PRAGMA application_id = 1196437809;
INSERT INTO meta(key, value) VALUES ('application', 'tinbase');
