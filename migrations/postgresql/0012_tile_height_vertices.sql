-- 0012 (PostgreSQL): a vertex at the lowest and one at the highest height of each tile pyramid's
-- surface (migrations/sqlite/0012_tile_height_vertices.sql).
ALTER TABLE tile_pyramids ADD COLUMN min_vertex bigint;
ALTER TABLE tile_pyramids ADD COLUMN max_vertex bigint;
