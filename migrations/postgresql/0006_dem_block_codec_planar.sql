-- 0006 (PostgreSQL): the block codecs this store may hold.
INSERT INTO meta(key, value) VALUES ('dem_block_codecs', '1,2')
  ON CONFLICT (key) DO UPDATE SET value = excluded.value;
