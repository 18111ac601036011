-- 0013 (PostgreSQL): meta's application row, by which tinbase knows its own stores (as
-- migrations/sqlite/0013_geopackage_application_id.sql). A PostgreSQL store keeps its
-- application id in tinbase_store: there is no GeoPackage header to share.
INSERT INTO meta(key, value) VALUES ('application', 'tinbase');
