-- The store CREATE EXTENSION tinbase makes (schema terrain) is the store `tinbase init` makes
-- (schema cli_made, by tests/pgtap/run_pgtap.sh): the same tables and columns, keys and checks,
-- indexes, triggers, views and identity, read from the catalogs with the schema names taken out.
-- (terrain holds a surface by now; only definitions and the identity rows are compared.)
BEGIN;
SET search_path TO public;
SELECT plan(8);

CREATE TEMP VIEW columns_of AS
SELECT table_schema AS s, table_name, column_name, data_type, is_nullable, column_default
FROM information_schema.columns WHERE table_schema IN ('terrain', 'cli_made');

SELECT bag_eq(
  $$SELECT table_name, column_name, data_type, is_nullable, column_default FROM columns_of
    WHERE s = 'terrain'$$,
  $$SELECT table_name, column_name, data_type, is_nullable, column_default FROM columns_of
    WHERE s = 'cli_made'$$,
  'the same tables and views with the same columns');
SELECT bag_eq(
  $$SELECT c.conrelid::regclass::text AS tab, c.conname, c.contype,
           pg_get_constraintdef(c.oid) AS def
    FROM pg_constraint c WHERE c.connamespace = 'terrain'::regnamespace$$,
  $$SELECT replace(c.conrelid::regclass::text, 'cli_made.', 'terrain.') AS tab, c.conname,
           c.contype, replace(pg_get_constraintdef(c.oid), 'cli_made.', 'terrain.') AS def
    FROM pg_constraint c WHERE c.connamespace = 'cli_made'::regnamespace$$,
  'the same keys, references and checks');
SELECT bag_eq(
  $$SELECT indexname, replace(indexdef, 'terrain.', '') AS def FROM pg_indexes
    WHERE schemaname = 'terrain'$$,
  $$SELECT indexname, replace(indexdef, 'cli_made.', '') AS def FROM pg_indexes
    WHERE schemaname = 'cli_made'$$,
  'the same indexes');
SELECT bag_eq(
  $$SELECT trigger_name, event_manipulation, event_object_table, action_timing,
           replace(action_statement, 'terrain.', '') AS def
    FROM information_schema.triggers WHERE trigger_schema = 'terrain'$$,
  $$SELECT trigger_name, event_manipulation, event_object_table, action_timing,
           replace(action_statement, 'cli_made.', '') AS def
    FROM information_schema.triggers WHERE trigger_schema = 'cli_made'$$,
  'the same triggers');
SELECT bag_eq(
  $$SELECT viewname, replace(definition, 'terrain.', '') AS def FROM pg_views
    WHERE schemaname = 'terrain'$$,
  $$SELECT viewname, replace(definition, 'cli_made.', '') AS def FROM pg_views
    WHERE schemaname = 'cli_made'$$,
  'the same views');
SELECT is_empty(
  $$SELECT proname FROM pg_proc WHERE pronamespace = 'cli_made'::regnamespace
    EXCEPT SELECT proname FROM pg_proc WHERE pronamespace = 'terrain'::regnamespace$$,
  'every function of the CLI''s store is in the extension''s');
SELECT results_eq('SELECT * FROM terrain.tinbase_store', 'SELECT * FROM cli_made.tinbase_store',
                  'the same identity and schema version');
SELECT bag_eq(
  $$SELECT key, value FROM terrain.meta WHERE key IN ('application', 'dem_block_codecs')$$,
  $$SELECT key, value FROM cli_made.meta$$,
  'the same rows of meta from the migrations');

SELECT * FROM finish();
ROLLBACK;
