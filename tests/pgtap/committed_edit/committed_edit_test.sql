-- pgTAP tests of a committed edit of the extension (run by tests/pgtap/run_pgtap.sh once the read
-- and transaction tests are done): run_pgtap.sh committed tinbase_add_polygon of a square to the
-- store `terrain`, added the same square with `tinbase polygon add` to `twin` (the same surface
-- built by the CLI), and ran `tinbase check --full` on both. The two stores now hold the same rows:
-- the engine inside the server made the CLI's edit. Only the times of the changes rows differ.
BEGIN;
SET search_path TO public;
SELECT plan(8);

SELECT is((SELECT count(*) FROM terrain.features), 1::bigint, 'the committed feature is there');
SELECT results_eq('SELECT id, surface, x, y, z, kind FROM terrain.vertices ORDER BY id',
                  'SELECT id, surface, x, y, z, kind FROM twin.vertices ORDER BY id',
                  'the same vertices as the CLI''s edit');
SELECT results_eq(
  'SELECT t.id, v0, v1, v2, n0, n1, n2, visible, g.value, block FROM terrain.triangles t
     LEFT JOIN terrain.tags g ON g.id = t.tag ORDER BY t.id',
  'SELECT t.id, v0, v1, v2, n0, n1, n2, visible, g.value, block FROM twin.triangles t
     LEFT JOIN twin.tags g ON g.id = t.tag ORDER BY t.id',
  'the same triangles, links, visibility and tags');
SELECT results_eq('SELECT surface, va, vb, feature FROM terrain.constraints ORDER BY 1, 2, 3',
                  'SELECT surface, va, vb, feature FROM twin.constraints ORDER BY 1, 2, 3',
                  'the same constraints');
SELECT results_eq(
  'SELECT id, surface, mode, level, attributes, geometry, min_x, min_y, max_x, max_y, tx
     FROM terrain.features ORDER BY id',
  'SELECT id, surface, mode, level, attributes, geometry, min_x, min_y, max_x, max_y, tx
     FROM twin.features ORDER BY id',
  'the same feature row');
SELECT results_eq(
  'SELECT tx, surface, feature, action, removed, added, min_x, min_y, max_x, max_y
     FROM terrain.changes ORDER BY tx',
  'SELECT tx, surface, feature, action, removed, added, min_x, min_y, max_x, max_y
     FROM twin.changes ORDER BY tx',
  'the same changes rows (but their times)');
SELECT results_eq('SELECT feature, tx, present, mode, geometry FROM terrain.feature_versions
                     ORDER BY 1, 2',
                  'SELECT feature, tx, present, mode, geometry FROM twin.feature_versions
                     ORDER BY 1, 2',
                  'the same feature versions');
SELECT is_empty($$SELECT * FROM terrain.tinbase_check('terrain')$$,
                'tinbase_check finds nothing either');

SELECT * FROM finish();
ROLLBACK;
