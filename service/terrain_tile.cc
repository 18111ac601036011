// Taking refused extensions out of a stored tile.
#include "service/terrain_tile.h"

#include <vector>

#include "core/tiles/quantized_mesh.h"

namespace tinbase::service {

Result<std::string> TileKeeping(const std::string& stored, const TileExtensions& built,
                                const TileExtensions& keep, const std::string& source) {
  const bool drop_normals = built.normals && !keep.normals;
  const bool drop_water = built.water_mask && !keep.water_mask;
  const bool drop_metadata = built.metadata && !keep.metadata;
  if (!drop_normals && !drop_water && !drop_metadata) return stored;
  auto mesh = DecodeQuantizedMesh(std::vector<uint8_t>(stored.begin(), stored.end()), source);
  if (!mesh.ok()) return Status::Corruption(mesh.status().message());
  if (drop_normals) mesh->normals.reset();
  if (drop_water) mesh->water_mask.reset();
  if (drop_metadata) mesh->metadata.reset();
  TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(*mesh));
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace tinbase::service
