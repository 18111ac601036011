-- 0005: block extents without their cells. Window reads list the blocks of a window with their
-- min and max; zmin and zmax follow the compressed blob in each row, so reading them from the
-- table walked every overflow page of the blob even when the block was already decoded in memory.
CREATE INDEX dem_blocks_extent ON dem_blocks(dem, level, by, bx, zmin, zmax);
