-- 0012: a vertex at the lowest and one at the highest height of each tile pyramid's surface, so
-- that an update can tell whether an edit moved the height range without reading every vertex
-- (docs/tiles.md, "Updates"). NULL for pyramids built before: their next update reads them all.
ALTER TABLE tile_pyramids ADD COLUMN min_vertex INTEGER;
ALTER TABLE tile_pyramids ADD COLUMN max_vertex INTEGER;
