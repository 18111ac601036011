#include "core/export/mesh_selection.h"

namespace tinbase {

MeshSelection SelectTriangles(const Tin& tin, bool visible_only) {
  MeshSelection s;
  s.output_index.assign(tin.vertices.size(), -1);
  if (!visible_only) {
    s.triangles.resize(tin.triangles.size());
    for (size_t t = 0; t < tin.triangles.size(); ++t) s.triangles[t] = static_cast<uint32_t>(t);
    s.vertices.resize(tin.vertices.size());
    for (size_t v = 0; v < tin.vertices.size(); ++v) {
      s.vertices[v] = static_cast<uint32_t>(v);
      s.output_index[v] = static_cast<int64_t>(v);
    }
    return s;
  }
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    if (!tri.visible) continue;
    s.triangles.push_back(static_cast<uint32_t>(t));
    for (uint32_t v : tri.v) {
      if (s.output_index[v] >= 0) continue;
      s.output_index[v] = static_cast<int64_t>(s.vertices.size());
      s.vertices.push_back(v);
    }
  }
  return s;
}

}  // namespace tinbase
