-- 0006: DEM blocks may be stored with codec 2 (planar prediction + Blosc/zstd, docs/format.md).
-- No table changes: the version number is the point. A tinbase that knows only codec 1 stops at
-- schema 5 and so refuses this store up front ("made by a newer tinbase") instead of failing on
-- the first block it cannot decode. The codecs a store may hold are recorded for tools.
INSERT OR REPLACE INTO meta(key, value) VALUES ('dem_block_codecs', '1,2');
