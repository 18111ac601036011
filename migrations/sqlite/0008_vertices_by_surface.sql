-- 0008: vertices are indexed by surface alone. Nothing looks a vertex up by its coordinates
-- (point location walks the triangles), and the (surface, x, y) index put every new ring vertex
-- of an edit on its own leaf page: a fifth of the pages each committed polygon wrote to the WAL.
-- By surface, new vertices (ever larger ids) go at the end, and min(id) / max(id) of a surface,
-- which every full read of a surface starts with, are one seek instead of a scan of the index.
DROP INDEX vertices_surface_xy;
CREATE INDEX vertices_surface ON vertices(surface);
