-- pgTAP tests of the PostgreSQL extension (run by tests/pgtap/run_pgtap.sh, which made the store
-- `terrain` with CREATE EXTENSION tinbase, built its surface with the CLI and recorded the CLI's
-- answers in public.cli_answers). The functions are called schema-qualified from a search_path
-- without the store on it: they find their tables themselves.
BEGIN;
SET search_path TO public;
SELECT plan(31);

-- The extension makes a store, as `tinbase init` does.
SELECT has_extension('tinbase');
SELECT has_table('terrain', 'triangles', 'triangles');
SELECT has_table('terrain', 'vertices', 'vertices');
SELECT has_table('terrain', 'features', 'features');
SELECT has_table('terrain', 'changes', 'changes');
SELECT has_view('terrain', 'tinbase_triangles', 'the PostGIS view of triangles');
SELECT results_eq(
  'SELECT application_id, schema_version FROM terrain.tinbase_store',
  $$SELECT 1414090306, extversion::integer FROM pg_extension WHERE extname = 'tinbase'$$,
  'the store row: tinbase''s application id, the schema version of the extension''s version');
SELECT is((SELECT value FROM terrain.meta WHERE key = 'application'), 'tinbase',
          'meta''s application row of migration 0013');
SELECT is((SELECT array_length(extconfig, 1) FROM pg_extension WHERE extname = 'tinbase'),
          (SELECT count(*)::integer - 1 FROM pg_tables WHERE schemaname = 'terrain'
             AND tablename IN (SELECT relname FROM pg_class c JOIN pg_depend d ON d.objid = c.oid
                               WHERE d.refobjid = (SELECT oid FROM pg_extension
                                                   WHERE extname = 'tinbase')))
          + (SELECT count(*)::integer FROM pg_class c JOIN pg_depend d ON d.objid = c.oid
             WHERE c.relkind = 'S' AND c.relnamespace = 'terrain'::regnamespace
               AND d.refobjid = (SELECT oid FROM pg_extension WHERE extname = 'tinbase')),
          'pg_dump keeps the rows of every table but tinbase_store, and the id sequences');

-- The read functions give the CLI's answers.
SELECT cmp_ok((SELECT count(*) FROM cli_answers WHERE triangle IS NOT NULL), '>', 250::bigint,
              'most points fall on the surface');
SELECT cmp_ok((SELECT count(*) FROM cli_answers WHERE triangle IS NULL), '>', 0::bigint,
              'some fall outside it');
SELECT is((SELECT count(*) FROM cli_answers
           WHERE terrain.tinbase_locate('terrain', x, y) IS DISTINCT FROM triangle), 0::bigint,
          'tinbase_locate finds the CLI''s triangle for every point, NULL outside');
SELECT is((SELECT count(*) FROM (SELECT z, terrain.tinbase_z('terrain', x, y) AS sql_z
                                 FROM cli_answers) a
           WHERE (sql_z IS NULL) <> (z IS NULL) OR abs(sql_z - z) > 1e-6), 0::bigint,
          'tinbase_z gives the CLI''s z for every point (to a micrometre), NULL outside');
SELECT is(terrain.tinbase_locate('terrain', ST_MakePoint(540000, 7500000)),
          terrain.tinbase_locate('terrain', 540000, 7500000), 'tinbase_locate takes a point');
SELECT is((SELECT count(*) FROM (SELECT t.id, t.n0, t.n1, t.n2 FROM terrain.triangles t
                                 ORDER BY t.id LIMIT 200) t
           WHERE ARRAY(SELECT terrain.tinbase_neighbours('terrain', t.id))
                 IS DISTINCT FROM ARRAY(SELECT n FROM unnest(ARRAY[t.n0, t.n1, t.n2]) n
                                        WHERE n IS NOT NULL)), 0::bigint,
          'tinbase_neighbours gives the triangles across the edges, in edge order');

-- tinbase_profile gives the CLI's stations along 20 random lines.
CREATE TEMP TABLE sql_profile AS
SELECT l.line, p.*
FROM profile_lines l,
  LATERAL terrain.tinbase_profile('terrain', ST_GeomFromText(l.wkt)) WITH ORDINALITY
    AS p(distance, x, y, z, kind, triangle, visible, tag, seq);
SELECT cmp_ok((SELECT count(*) FROM cli_profile), '>', 100::bigint,
              'the CLI profiled the lines (they cross many triangles)');
SELECT is((SELECT count(*) FROM sql_profile), (SELECT count(*) FROM cli_profile),
          'tinbase_profile gives as many stations');
SELECT is((SELECT count(*) FROM cli_profile c FULL JOIN sql_profile s USING (line, seq)
           WHERE c.kind IS DISTINCT FROM s.kind OR c.triangle IS DISTINCT FROM s.triangle
              OR c.visible IS DISTINCT FROM s.visible OR c.tag IS DISTINCT FROM s.tag
              OR abs(c.distance - s.distance) > 1e-6 OR abs(c.x - s.x) > 1e-6
              OR abs(c.y - s.y) > 1e-6 OR abs(c.z - s.z) > 1e-6
              OR s.line IS NULL OR c.line IS NULL), 0::bigint,
          'each station of the same kind, place, z and stretch, in the same order');
SELECT throws_like(
  $$SELECT * FROM terrain.tinbase_profile('terrain', 'LINESTRING(530000 7490000, 0 0)'::geometry)$$,
  'tinbase_profile: the line leaves the surface at % on its way to point 2',
  'a line that leaves the surface is refused, naming where');

-- tinbase_check finds what `tinbase check` finds, with the same codes and words.
SELECT is_empty($$SELECT * FROM terrain.tinbase_check('terrain')$$, 'a sound surface has no problems');
SELECT cmp_ok((SELECT count(*) FROM cli_problems), '>=', 5::bigint,
              'the damage run_pgtap.sh made was seen by the CLI');
SELECT bag_eq('SELECT * FROM sql_problems', 'SELECT * FROM cli_problems',
              'tinbase_check reported the CLI''s problems on the damaged surface');
SELECT throws_ok($$SELECT * FROM terrain.tinbase_check('nowhere')$$, '22023',
                 'tinbase_check: no surface named ''nowhere''', 'tinbase_check names an unknown surface');

-- Bad input is refused with an error naming it, and changes nothing.
SELECT throws_ok($$SELECT terrain.tinbase_z('nowhere', 0, 0)$$, '22023',
                 'tinbase_z: no surface named ''nowhere''', 'an unknown surface is named');
SELECT throws_ok($$SELECT terrain.tinbase_z('x''); DROP TABLE terrain.triangles; --', 0, 0)$$,
                 '22023', NULL, 'a surface name is a value, never SQL');
SELECT has_table('terrain', 'triangles', 'triangles is still there');
SELECT throws_ok($$SELECT terrain.tinbase_neighbours('terrain', -5)$$, '22023',
                 NULL, 'an unknown triangle is refused');
SELECT throws_like($$SELECT terrain.tinbase_neighbours('terrain', -5)$$,
                   'tinbase_neighbours: %triangle -5%', 'an unknown triangle is named');

-- The functions read in the caller's transaction: they see its own uncommitted edit, and a
-- rollback takes it away again.
CREATE TEMP TABLE before AS SELECT terrain.tinbase_z('terrain', 540000, 7500000) AS z;
SAVEPOINT raised;
UPDATE terrain.vertices SET z = z + 100 WHERE id IN (
  SELECT unnest(ARRAY[v0, v1, v2]) FROM terrain.triangles
  WHERE id = terrain.tinbase_locate('terrain', 540000, 7500000));
SELECT cmp_ok(abs(terrain.tinbase_z('terrain', 540000, 7500000) - (SELECT z + 100 FROM before)),
              '<', 1e-6::double precision, 'an uncommitted edit is seen by tinbase_z');
ROLLBACK TO SAVEPOINT raised;
SELECT is(terrain.tinbase_z('terrain', 540000, 7500000), (SELECT z FROM before),
          'a rollback undoes it');
SELECT is(terrain.tinbase_z('terrain', 1e9, 1e9), NULL, 'NULL far outside');

SELECT * FROM finish();
ROLLBACK;
