// The triangle object of the API.
#include "service/triangle_json.h"

#include "db/mesh/mesh_tables.h"
#include "service/client_crs.h"

namespace tinbase::service {

TriangleView ViewOf(const TriangleNeighbours& t) {
  TriangleView view;
  view.id = t.triangle;
  // edges[i] runs from corner i + 1 to corner i + 2 (topology.h), so its ends name them all.
  view.corners = {t.edges[1].ends[1], t.edges[0].ends[0], t.edges[0].ends[1]};
  for (int i = 0; i < 3; ++i) view.neighbours[i] = t.row.n[i];
  view.visible = t.row.visible;
  view.tag = t.tag;
  return view;
}

Result<std::vector<TriangleView>> ViewsOf(Store& store, const SurfaceInfo& surface,
                                          const LoadedSurface& selected) {
  MeshTables tables(store.db(), surface);
  const Tin& tin = selected.tin;
  std::vector<TriangleView> views(tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    TriangleView& view = views[t];
    view.id = selected.triangle_ids[t];
    bool cut = false;
    for (int i = 0; i < 3; ++i) {
      view.corners[i] = tin.vertices[tri.v[i]];
      if (tri.n[i] == kNoNeighbour) {
        cut = true;
      } else {
        view.neighbours[i] = selected.triangle_ids[static_cast<size_t>(tri.n[i])];
      }
    }
    view.visible = tri.visible;
    if (tri.tag != kNoTag) view.tag = tin.tags[static_cast<size_t>(tri.tag)];
    if (cut) {
      // The stored row knows what lies across the selection's edge (or that nothing does). Its
      // corners are in the same order as the loaded triangle's (SurfaceStore keeps them).
      TB_ASSIGN_OR_RETURN(TriangleRow row, tables.Triangle(view.id));
      view.neighbours = row.n;
    }
  }
  return views;
}

Result<nlohmann::json> TrianglesJson(const std::vector<TriangleView>& views,
                                     const StoreCrs* store_crs) {
  std::vector<TinVertex> corners;
  corners.reserve(views.size() * 3);
  for (const TriangleView& v : views)
    corners.insert(corners.end(), v.corners.begin(), v.corners.end());
  std::vector<TinVertex> lonlat;
  if (store_crs != nullptr) {
    lonlat = corners;
    TB_RETURN_IF_ERROR(store_crs->ToLonLat(lonlat));
  }
  nlohmann::json out = nlohmann::json::array();
  for (size_t t = 0; t < views.size(); ++t) {
    const TriangleView& v = views[t];
    nlohmann::json xyz = nlohmann::json::array(), geo = nlohmann::json::array(),
                   neighbours = nlohmann::json::array();
    for (int i = 0; i < 3; ++i) {
      xyz.push_back({v.corners[i].x, v.corners[i].y, v.corners[i].z});
      if (store_crs != nullptr) {
        const TinVertex& g = lonlat[t * 3 + static_cast<size_t>(i)];
        geo.push_back({g.x, g.y, g.z});
      }
      neighbours.push_back(v.neighbours[i] ? nlohmann::json(*v.neighbours[i])
                                           : nlohmann::json(nullptr));
    }
    out.push_back({{"id", v.id},
                   {"vertices", xyz},
                   {"lonlat", store_crs != nullptr ? geo : nlohmann::json(nullptr)},
                   {"neighbours", neighbours},
                   {"visible", v.visible},
                   {"tag", v.tag ? nlohmann::json(*v.tag) : nlohmann::json(nullptr)}});
  }
  return out;
}

}  // namespace tinbase::service
