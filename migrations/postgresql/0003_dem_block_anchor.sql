-- 0003 (PostgreSQL): where the DEM's block grid is anchored, from its first source (as
-- migrations/sqlite/0003_dem_block_anchor.sql, with jsonb for SQLite's json functions).
ALTER TABLE dems ADD COLUMN block_col0 bigint NOT NULL DEFAULT 0;
ALTER TABLE dems ADD COLUMN block_row0 bigint NOT NULL DEFAULT 0;
UPDATE dems SET
  block_col0 = round(((sources::jsonb -> 0 ->> 'origin_x')::double precision - origin_x) / cell_x),
  block_row0 = round(((sources::jsonb -> 0 ->> 'origin_y')::double precision - origin_y) / cell_y)
WHERE jsonb_array_length(sources::jsonb) > 0
  AND sources::jsonb -> 0 ->> 'origin_x' IS NOT NULL
  AND sources::jsonb -> 0 ->> 'origin_y' IS NOT NULL;
