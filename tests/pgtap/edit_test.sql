-- pgTAP tests of the extension's edit functions in the caller's transaction (run by
-- tests/pgtap/run_pgtap.sh with the others, before any edit is committed): an edit shows inside
-- the transaction and a rollback leaves every table of the store as it was, by checksums; bad
-- input is refused with an error naming it, and changes nothing. The committed edit, checked by
-- the CLI and against the CLI's own edit, is committed_edit/committed_edit_test.sql.
BEGIN;
SET search_path TO public;
SELECT plan(22);

-- Every table of the store with the md5 of its rows in a fixed order.
CREATE FUNCTION pg_temp.store_sums() RETURNS TABLE(name text, sum text) LANGUAGE plpgsql AS $$
DECLARE
  t text;
BEGIN
  FOR t IN SELECT tablename FROM pg_tables WHERE schemaname = 'terrain' ORDER BY 1 LOOP
    name := t;
    EXECUTE format('SELECT coalesce(md5(string_agg(r::text, %L ORDER BY r::text)), %L) '
                   'FROM terrain.%I r', ',', '', t) INTO sum;
    RETURN NEXT;
  END LOOP;
END $$;
CREATE TEMP TABLE before AS SELECT * FROM pg_temp.store_sums();
CREATE TEMP TABLE square AS SELECT
  'POLYGON((530000 7490000, 534000 7490000, 534000 7494000, 530000 7494000, 530000 7490000))'
  ::geometry AS g;

-- An edit inside a savepoint: seen by the caller's transaction, gone after the rollback.
SAVEPOINT edit;
CREATE TEMP TABLE added AS
  SELECT terrain.tinbase_add_polygon('terrain', g, 'fill', 'lake') AS id FROM square;
SELECT cmp_ok((SELECT id FROM added), '>', 0::bigint, 'tinbase_add_polygon gives the feature id');
SELECT is((SELECT mode FROM terrain.features WHERE id = (SELECT id FROM added)), 'fill',
          'the feature row is there inside the transaction');
SELECT is((SELECT count(*) FROM terrain.changes WHERE feature = (SELECT id FROM added)), 1::bigint,
          'with its changes row');
SELECT is((SELECT g.value FROM terrain.triangles t JOIN terrain.tags g ON g.id = t.tag
           WHERE t.id = terrain.tinbase_locate('terrain', 532000, 7492000)), 'lake',
          'tinbase_locate sees the painted triangles of the uncommitted edit');
SELECT isnt_empty('SELECT * FROM pg_temp.store_sums() EXCEPT SELECT * FROM before',
                  'the edit changed the tables');
SELECT cmp_ok(terrain.tinbase_remove_feature('terrain', (SELECT id FROM added)), '>', 0::bigint,
              'tinbase_remove_feature gives its transaction number');
SELECT is((SELECT count(*) FROM terrain.features WHERE id = (SELECT id FROM added)), 0::bigint,
          'the removed feature is gone');
ROLLBACK TO SAVEPOINT edit;
SELECT results_eq('SELECT * FROM pg_temp.store_sums() ORDER BY 1', 'SELECT * FROM before ORDER BY 1',
                  'a rollback leaves every table of the store as it was');

-- Bad input: an error naming the argument and the problem.
SELECT throws_ok($$SELECT terrain.tinbase_add_polygon('nowhere', g, 'fill', NULL) FROM square$$,
                 '22023', 'tinbase_add_polygon: no surface named ''nowhere''',
                 'an unknown surface is named');
SELECT throws_ok($$SELECT terrain.tinbase_add_polygon('terrain', g, 'flood', NULL) FROM square$$,
                 '22023',
                 'tinbase_add_polygon: argument 4 (mode): unknown feature mode ''flood'' (expected '
                 'clip, erase, fill, replace, breakline, softline or points)',
                 'an unknown mode is named');
SELECT throws_like(
  $$SELECT terrain.tinbase_add_polygon('terrain', 'POLYGON((530000 7490000, 534000 7494000,
      534000 7490000, 530000 7494000, 530000 7490000))'::geometry, 'fill', NULL)$$,
  'tinbase_add_polygon: argument 2 (geometry), ring 0%crosses itself%',
  'a ring that crosses itself is refused, naming the ring');
SELECT throws_like(
  $$SELECT terrain.tinbase_add_polygon('terrain', ST_MakePolygon(ST_MakeLine(ARRAY[
      ST_MakePoint(530000, 7490000), ST_MakePoint('NaN', 7490000), ST_MakePoint(534000, 7494000),
      ST_MakePoint(530000, 7490000)])), 'fill', NULL)$$,
  'tinbase_add_polygon: argument 2 (geometry), ring 0, vertex 1%',
  'a NaN coordinate is refused, naming the vertex');
SELECT throws_like(
  $$SELECT terrain.tinbase_add_polygon('terrain', 'POINT(530000 7490000)'::geometry, 'fill')$$,
  'tinbase_add_polygon: argument 2 (geometry): mode fill takes a Polygon or MultiPolygon, got Point',
  'a point is not a polygon');
SELECT throws_like(
  $$SELECT terrain.tinbase_add_polygon('terrain', ST_SetSRID(g, 4326), 'fill') FROM square$$,
  'tinbase_add_polygon: argument 2 (geometry): SRID 4326 is not the store''s EPSG:%',
  'a geometry in another CRS is refused');
SELECT throws_like(
  $$SELECT terrain.tinbase_add_polygon('terrain', 'POLYGON((0 0, 10 0, 10 10, 0 0))'::geometry,
                                       'fill')$$,
  'tinbase_add_polygon: %outside%', 'a polygon outside the surface is refused');
SELECT throws_ok($$SELECT terrain.tinbase_remove_feature('terrain', 999999)$$, '22023',
                 'tinbase_remove_feature: surface ''terrain'' has no feature 999999',
                 'an unknown feature is named');
SELECT throws_ok($$SELECT terrain.tinbase_z('terrain', 'NaN', 7490000)$$, '22023',
                 'tinbase_z: argument 2 (x) must be a finite number', 'a NaN point is refused');
SELECT throws_ok($$SELECT terrain.tinbase_add_polygon('terrain', NULL, 'fill')$$, '22004',
                 'tinbase_add_polygon: surface, geometry and mode must not be NULL',
                 'a NULL geometry is refused');

-- A server error in the middle of the edit (a trigger that refuses a triangle row): raised as the
-- function's error, nothing of the edit kept, and the next edit of the transaction works.
CREATE FUNCTION public.refuse_row() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  RAISE EXCEPTION 'refused by a test trigger';
END $$;
CREATE TRIGGER refuse BEFORE INSERT ON terrain.triangles
  FOR EACH ROW EXECUTE FUNCTION public.refuse_row();
SELECT throws_like($$SELECT terrain.tinbase_add_polygon('terrain', g, 'fill') FROM square$$,
                   'tinbase_add_polygon: %refused by a test trigger',
                   'a server error inside the edit is the function''s error');
DROP TRIGGER refuse ON terrain.triangles;
SELECT results_eq('SELECT * FROM pg_temp.store_sums() ORDER BY 1', 'SELECT * FROM before ORDER BY 1',
                  'the refused calls changed nothing');
SAVEPOINT again;
SELECT cmp_ok(terrain.tinbase_add_polygon('terrain', g, 'fill'), '>', 0::bigint,
              'an edit after the failed one works') FROM square;
ROLLBACK TO SAVEPOINT again;
SELECT results_eq('SELECT * FROM pg_temp.store_sums() ORDER BY 1', 'SELECT * FROM before ORDER BY 1',
                  'and its rollback leaves the store as it was');

SELECT * FROM finish();
ROLLBACK;
