-- 0017 (PostgreSQL): ids and change numbers come from sequences, so that writers of distant
-- regions of one surface can commit at once (docs/scaling.md, "Writers"). Until now a trigger
-- numbered each new row 1 + the largest id of its table, which two concurrent writers read alike.
-- A sequence hands out each number once, whatever commits or rolls back; ids are no longer dense
-- (nothing reads meaning into density). Each sequence starts past every id its table holds, and
-- the features' past every feature id a version names (a removed feature's id never comes back).
CREATE SEQUENCE dems_id_seq;
CREATE SEQUENCE surfaces_id_seq;
CREATE SEQUENCE vertices_id_seq;
CREATE SEQUENCE tags_id_seq;
CREATE SEQUENCE triangles_id_seq;
CREATE SEQUENCE features_id_seq;
CREATE SEQUENCE changes_tx_seq;
SELECT setval('dems_id_seq', (SELECT coalesce(max(id), 0) + 1 FROM dems), false);
SELECT setval('surfaces_id_seq', (SELECT coalesce(max(id), 0) + 1 FROM surfaces), false);
SELECT setval('vertices_id_seq', (SELECT coalesce(max(id), 0) + 1 FROM vertices), false);
SELECT setval('tags_id_seq', (SELECT coalesce(max(id), 0) + 1 FROM tags), false);
SELECT setval('triangles_id_seq', (SELECT coalesce(max(id), 0) + 1 FROM triangles), false);
SELECT setval('features_id_seq',
              (SELECT coalesce(max(m), 0) + 1 FROM (SELECT max(id) AS m FROM features
                                                   UNION ALL
                                                   SELECT max(feature) FROM feature_versions) u),
              false);
SELECT setval('changes_tx_seq', (SELECT coalesce(max(tx), 0) + 1 FROM changes), false);

-- The triggers keep their names and their rule (a row given an id keeps it); only the number
-- they give changes.
CREATE OR REPLACE FUNCTION tinbase_dems_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('dems_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_surfaces_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('surfaces_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_vertices_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('vertices_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_tags_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('tags_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_triangles_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('triangles_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_features_id() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.id IS NULL THEN NEW.id := nextval('features_id_seq'); END IF;
  RETURN NEW;
END $$;
CREATE OR REPLACE FUNCTION tinbase_changes_tx() RETURNS trigger LANGUAGE plpgsql AS $$
BEGIN
  IF NEW.tx IS NULL THEN NEW.tx := nextval('changes_tx_seq'); END IF;
  RETURN NEW;
END $$;

-- `n` consecutive fresh numbers of sequence `seq` (n >= 1); returns the first. The engine numbers
-- a patch's rows before writing them (neighbour links name rows of the same batch), so it needs a
-- run, not n numbers that other writers' calls may interleave. The session lock makes the
-- nextval and the setval one step for every caller; it is held for these two calls only, never
-- until the transaction ends, so writers do not wait on each other's edits here.
CREATE FUNCTION tinbase_reserve_ids(seq regclass, n bigint) RETURNS bigint LANGUAGE plpgsql AS $$
DECLARE
  first bigint;
BEGIN
  IF n < 1 THEN
    RAISE EXCEPTION 'tinbase_reserve_ids: % numbers asked for, at least 1 expected', n;
  END IF;
  PERFORM pg_advisory_lock(1953063522, seq::oid::integer);
  BEGIN
    first := nextval(seq);
    IF n > 1 THEN PERFORM setval(seq, first + n - 1); END IF;
  EXCEPTION WHEN OTHERS THEN
    PERFORM pg_advisory_unlock(1953063522, seq::oid::integer);
    RAISE;
  END;
  PERFORM pg_advisory_unlock(1953063522, seq::oid::integer);
  RETURN first;
END $$;
