#include "db/export/landxml_export.h"

#include <algorithm>
#include <tuple>
#include <unordered_map>

#include "core/base/output_file.h"
#include "core/export/landxml_writer.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

LandXmlFeature FromEditor(const EditorFeature& f) {
  LandXmlFeature out;
  out.name = f.tag.value_or(f.label);
  out.mode = f.mode;
  out.tag = f.tag;
  out.level = f.level;
  out.attributes = f.attributes.dump();
  out.polygons = f.polygons;
  out.lines = f.lines;
  out.z_from = f.z_from;
  out.line_z = f.line_z;
  return out;
}

void SetCrs(const std::optional<Crs>& crs, LandXmlSurface& out) {
  if (!crs) return;
  out.crs_wkt = crs->Wkt();
  out.epsg = crs->Epsg();
  out.crs_name = crs->Label();
  out.metres_per_unit = crs->IsGeographic() ? 1.0 : crs->VerticalMetresPerUnit();
}

LandXmlSurface Header(const SurfaceInfo& surface) {
  LandXmlSurface out;
  out.name = surface.name;
  out.kind = SurfaceKindName(surface.kind);
  out.method = surface.method;
  out.tolerance = surface.tolerance;
  return out;
}

// The constraint rows of `surface` with owners, as vertex and feature indices.
Status LoadConstraintOwners(Store& store, const SurfaceInfo& surface, const LoadedSurface& loaded,
                            const std::vector<EditorFeature>& features, LandXmlSurface& out) {
  std::unordered_map<int64_t, uint32_t> vertex_index;
  vertex_index.reserve(loaded.vertex_ids.size());
  for (size_t i = 0; i < loaded.vertex_ids.size(); ++i)
    vertex_index.emplace(loaded.vertex_ids[i], static_cast<uint32_t>(i));
  std::unordered_map<int64_t, uint32_t> feature_index;
  for (size_t i = 0; i < features.size(); ++i)
    feature_index.emplace(features[i].id, static_cast<uint32_t>(i));
  MeshTables mesh(store.db(), surface);
  TB_ASSIGN_OR_RETURN(ConstraintCursor cursor, mesh.Constraints());
  for (ConstraintRow row;;) {
    TB_ASSIGN_OR_RETURN(bool more, cursor.Next(&row));
    if (!more) break;
    auto a = vertex_index.find(row.va), b = vertex_index.find(row.vb);
    if (a == vertex_index.end() || b == vertex_index.end())
      return Status::Corruption("surface '" + surface.name + "': constraint (" +
                                std::to_string(row.va) + ", " + std::to_string(row.vb) +
                                ") names a missing vertex");
    LandXmlConstraint c{a->second, b->second, std::nullopt};
    if (row.feature) {
      auto f = feature_index.find(*row.feature);
      if (f == feature_index.end())
        return Status::Corruption("surface '" + surface.name + "': constraint (" +
                                  std::to_string(row.va) + ", " + std::to_string(row.vb) +
                                  ") names feature " + std::to_string(*row.feature) +
                                  ", which is not one of its features");
      c.feature = f->second;
    }
    out.constraints.push_back(c);
  }
  return Status::Ok();
}

}  // namespace

Result<LandXmlSurface> LoadLandXmlSurface(Store& store, const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(LoadedSurface loaded, surfaces.Load(surface));
  TB_ASSIGN_OR_RETURN(std::vector<EditorFeature> features, LoadFeatures(store, surface));
  LandXmlSurface out = Header(surface);
  SetCrs(crs, out);
  if (surface.dem) {
    DemStore dems(store);
    TB_ASSIGN_OR_RETURN(DemInfo dem, dems.FindById(*surface.dem));
    out.dem = dem.name;
  }
  TB_RETURN_IF_ERROR(LoadConstraintOwners(store, surface, loaded, features, out));
  for (const EditorFeature& f : features) out.features.push_back(FromEditor(f));
  out.tin = std::move(loaded.tin);
  out.tin.constraints.clear();
  return out;
}

LandXmlSurface LandXmlFromLoaded(const SurfaceInfo& surface, const LoadedSurface& loaded,
                                 const std::optional<Crs>& crs) {
  LandXmlSurface out = Header(surface);
  SetCrs(crs, out);
  out.tin = loaded.tin;
  // A selection's constraints come one per stored row; without owners the rows of an edge that
  // several features share are the same.
  auto edges = out.tin.constraints;
  for (auto& [a, b] : edges) std::tie(a, b) = std::minmax(a, b);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) out.constraints.push_back({a, b, std::nullopt});
  out.tin.constraints.clear();
  return out;
}

Result<LandXmlSurface> LoadLandXmlSelection(Store& store, const SurfaceInfo& surface,
                                            const SurfaceFilter& filter) {
  const bool selects = filter.bbox || filter.feature != 0 || filter.visible_only || filter.tag;
  if (!selects) return LoadLandXmlSurface(store, surface);
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  TB_ASSIGN_OR_RETURN(LoadedSurface selected, SelectSurface(store, surface, filter));
  return LandXmlFromLoaded(surface, selected, crs);
}

Status ExportLandXml(const LandXmlSurface& surface, const std::string& path) {
  TB_ASSIGN_OR_RETURN(OutputFile file, OutputFile::Create(path));
  if (!WriteLandXml(surface, file.temp_path()).ok()) return Status::IOError("cannot write " + path);
  return file.Commit();
}

}  // namespace tinbase
