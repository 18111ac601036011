-- 0003: the DEM's block anchor as columns (it was derived from sources[0]'s origin).
-- block_col0 / block_row0: the level-0 column and row of the DEM grid where block (0, 0) begins
-- (docs/format.md, "Block anchor"). Existing rows are filled from their first source's origin.
ALTER TABLE dems ADD COLUMN block_col0 INTEGER NOT NULL DEFAULT 0;
ALTER TABLE dems ADD COLUMN block_row0 INTEGER NOT NULL DEFAULT 0;
UPDATE dems SET
  block_col0 = CAST(round((json_extract(sources, '$[0].origin_x') - origin_x) / cell_x) AS INTEGER),
  block_row0 = CAST(round((json_extract(sources, '$[0].origin_y') - origin_y) / cell_y) AS INTEGER)
WHERE json_array_length(sources) > 0
  AND json_extract(sources, '$[0].origin_x') IS NOT NULL
  AND json_extract(sources, '$[0].origin_y') IS NOT NULL;
