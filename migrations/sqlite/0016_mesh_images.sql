-- 0016: every edit transaction keeps the before-image of the mesh rows it changed
-- (docs/format.md, "Mesh images"), so that a revert returns the exact mesh. One row per edit
-- transaction: `image` is a zstd-compressed record of the triangle and vertex rows (by id) and
-- the constraint rows (by edge) the edit wrote, as they were before it, with a digest of how it
-- left them (db/history/mesh_image.h). Edits committed before this migration have no row and
-- are reverted by re-refinement.
CREATE TABLE mesh_images(
  tx      INTEGER PRIMARY KEY,
  surface INTEGER NOT NULL REFERENCES surfaces(id) ON DELETE CASCADE,
  image   BLOB NOT NULL
);
