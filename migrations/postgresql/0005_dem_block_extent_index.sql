-- 0005 (PostgreSQL): DEM blocks found by their place and height range.
CREATE INDEX dem_blocks_extent ON dem_blocks(dem, level, "by", bx, zmin, zmax);
