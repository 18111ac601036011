#include "db/import/landxml_import.h"

#include <algorithm>
#include <bit>
#include <unordered_map>

#include "db/change_log.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/integrity_check.h"
#include "db/mesh/mesh_edge.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {

namespace {

// The store takes the file's CRS when it has none; otherwise the two must be the same system.
Status MatchCrs(Store& store, const LandXmlSurface& file) {
  if (file.crs_wkt.empty()) return Status::Ok();
  auto crs = Crs::FromWkt(file.crs_wkt);
  if (!crs.ok())
    return Status::InvalidArgument("CoordinateSystem: ogcWktCode does not parse: " +
                                   crs.status().message());
  TB_ASSIGN_OR_RETURN(std::optional<Crs> current, store.GetCrs());
  if (!current) return store.SetCrs(*crs);
  if (!current->IsSame(*crs))
    return Status::InvalidArgument("CoordinateSystem: the file is in " + crs->Label() +
                                   ", the store in " + current->Label());
  return Status::Ok();
}

Result<SurfaceInfo> Spec(Store& store, const LandXmlSurface& file,
                         const LandXmlImportOptions& options) {
  SurfaceInfo spec;
  spec.name = options.surface.empty() ? file.name : options.surface;
  if (spec.name.empty())
    return Status::InvalidArgument("the file's Surface has no name: give --surface");
  if (!ParseSurfaceKind(file.kind, &spec.kind))
    return Status::InvalidArgument("unknown surface kind '" + file.kind + "'");
  spec.method = file.method.empty() ? "landxml" : file.method;
  spec.tolerance = file.tolerance;
  DemStore dems(store);
  if (options.dem) {
    TB_ASSIGN_OR_RETURN(DemInfo dem, dems.Find(*options.dem));
    spec.dem = dem.id;
  } else if (!file.dem.empty()) {
    auto dem = dems.Find(file.dem);
    if (dem.ok()) spec.dem = dem->id;
    if (!dem.ok() && dem.status().code() != StatusCode::kNotFound) return dem.status();
  }
  return spec;
}

Change ImportChange(const SurfaceInfo& surface, const Tin& tin) {
  Change change;
  change.surface = surface.id;
  change.action = "import landxml";
  change.added = static_cast<int64_t>(tin.triangles.size());
  Box box;
  for (const TinVertex& v : tin.vertices) box.Add(Point2{v.x, v.y});
  change.min_x = box.min_x, change.min_y = box.min_y;
  change.max_x = box.max_x, change.max_y = box.max_y;
  return change;
}

// The store id of each of the file's vertices, matched by x and y (unique in a surface), since
// SurfaceStore numbers the vertices in its own order.
Result<std::vector<int64_t>> VertexIds(Store& store, const SurfaceInfo& surface, const Tin& tin) {
  struct Key {
    uint64_t x, y;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    size_t operator()(const Key& k) const { return std::hash<uint64_t>()(k.x * 1000003u ^ k.y); }
  };
  const auto key = [](const TinVertex& v) {
    return Key{std::bit_cast<uint64_t>(v.x), std::bit_cast<uint64_t>(v.y)};
  };
  std::unordered_map<Key, uint32_t, KeyHash> index;
  index.reserve(tin.vertices.size());
  for (uint32_t i = 0; i < tin.vertices.size(); ++i) {
    const auto [it, inserted] = index.emplace(key(tin.vertices[i]), i);
    if (!inserted)
      return Status::InvalidArgument("points " + std::to_string(it->second + 1) + " and " +
                                     std::to_string(i + 1) + " share x and y");
  }
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(LoadedSurface stored, surfaces.Load(surface));
  std::vector<int64_t> ids(tin.vertices.size(), 0);
  for (size_t i = 0; i < stored.tin.vertices.size(); ++i) {
    auto it = index.find(key(stored.tin.vertices[i]));
    if (it == index.end()) return Status::Corruption("an imported vertex came back moved");
    ids[it->second] = stored.vertex_ids[i];
  }
  return ids;
}

Result<std::vector<int64_t>> WriteFeatures(Store& store, const SurfaceInfo& surface, int64_t tx,
                                           const LandXmlSurface& file) {
  std::vector<int64_t> ids;
  for (size_t i = 0; i < file.features.size(); ++i) {
    const LandXmlFeature& in = file.features[i];
    EditorFeature f;
    f.label = in.name.empty() ? "feature " + std::to_string(i + 1) : in.name;
    f.mode = in.mode;
    f.tag = in.tag;
    f.level = in.level;
    f.attributes = nlohmann::json::parse(in.attributes, nullptr, /*allow_exceptions=*/false);
    if (f.attributes.is_discarded() || !f.attributes.is_object())
      return Status::InvalidArgument("tinbase feature " + std::to_string(i + 1) +
                                     ": attributes are not a JSON object");
    f.polygons = in.polygons;
    f.lines = in.lines;
    f.z_from = in.z_from;
    f.line_z = in.line_z;
    TB_RETURN_IF_ERROR(WriteFeature(store, surface, tx, f));
    ids.push_back(f.id);
  }
  return ids;
}

Status WriteConstraints(Store& store, const SurfaceInfo& surface, const LandXmlSurface& file,
                        const std::vector<int64_t>& vertex_ids,
                        const std::vector<int64_t>& feature_ids) {
  std::vector<std::pair<MeshEdge, int64_t>> rows;
  rows.reserve(file.constraints.size());
  for (const LandXmlConstraint& c : file.constraints) {
    if (c.a == c.b) return Status::InvalidArgument("a constrained edge joins a point to itself");
    rows.emplace_back(EdgeKey(vertex_ids[c.a], vertex_ids[c.b]),
                      c.feature ? feature_ids[*c.feature] : 0);
  }
  std::sort(rows.begin(), rows.end());
  MeshTables mesh(store.db(), surface);
  return mesh.InsertConstraints(rows);
}

// The new surface must pass every check `tinbase check --full` makes before it is committed.
Status CheckNewSurface(Store& store, const SurfaceInfo& surface, const LandXmlSurface& file) {
  CheckOptions options;
  options.surface = surface.name;
  options.full = true;
  TB_ASSIGN_OR_RETURN(std::vector<Problem> problems, CheckStore(store, options));
  if (problems.empty()) return Status::Ok();
  // Visibility comes from the features and the DEM's nodata; without the DEM a triangle hidden
  // by nodata has no reason to be.
  std::string hint;
  if (problems.front().code == "wrong-visibility" && !surface.dem)
    hint = file.dem.empty() ? "; give --dem if DEM nodata hid it"
                            : "; the file's surface was draped on DEM '" + file.dem +
                                  "': import that DEM into the store or give --dem";
  return Status::InvalidArgument(
      "the file's surface does not pass the integrity check (" + problems.front().code +
      "): " + problems.front().message +
      (problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) + " more)" : "") +
      hint);
}

}  // namespace

Result<LandXmlImportReport> ImportLandXml(Store& store, const LandXmlSurface& file,
                                          const LandXmlImportOptions& options) {
  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  TB_RETURN_IF_ERROR(MatchCrs(store, file));
  TB_ASSIGN_OR_RETURN(SurfaceInfo spec, Spec(store, file, options));
  Tin tin = file.tin;
  tin.constraints.clear();  // written below with their owners
  SurfaceStore surfaces(store);
  LandXmlImportReport report;
  TB_ASSIGN_OR_RETURN(report.surface, surfaces.Create(spec, tin));
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, ImportChange(report.surface, tin)));
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> vertex_ids, VertexIds(store, report.surface, tin));
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> feature_ids,
                      WriteFeatures(store, report.surface, report.tx, file));
  TB_RETURN_IF_ERROR(WriteConstraints(store, report.surface, file, vertex_ids, feature_ids));
  TB_RETURN_IF_ERROR(CheckNewSurface(store, report.surface, file));
  TB_RETURN_IF_ERROR(tx->Commit());
  report.vertices = static_cast<int64_t>(tin.vertices.size());
  report.triangles = static_cast<int64_t>(tin.triangles.size());
  report.features = static_cast<int64_t>(file.features.size());
  report.constraints = static_cast<int64_t>(file.constraints.size());
  return report;
}

}  // namespace tinbase
