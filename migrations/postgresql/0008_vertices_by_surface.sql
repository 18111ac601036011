-- 0008 (PostgreSQL): vertices indexed by surface alone.
DROP INDEX vertices_surface_xy;
CREATE INDEX vertices_surface ON vertices(surface);
