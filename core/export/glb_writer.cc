#include "core/export/glb_writer.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <unordered_map>

#include "core/export/binary_out.h"
#include "core/export/crs_text.h"
#include "core/export/local_frame.h"

namespace tinbase {

namespace {

using nlohmann::json;

constexpr int kArrayBuffer = 34962;         // GL ARRAY_BUFFER
constexpr int kElementArrayBuffer = 34963;  // GL ELEMENT_ARRAY_BUFFER
constexpr int32_t kHiddenGroup = -2;        // the group of invisible triangles

// tinygltf's JSON value from nlohmann's (the extension objects are easier to write as json).
tinygltf::Value ToValue(const json& j) {
  switch (j.type()) {
    case json::value_t::boolean:
      return tinygltf::Value(j.get<bool>());
    case json::value_t::number_integer:
    case json::value_t::number_unsigned: {
      const int64_t i = j.get<int64_t>();
      if (i >= std::numeric_limits<int>::min() && i <= std::numeric_limits<int>::max())
        return tinygltf::Value(static_cast<int>(i));
      return tinygltf::Value(static_cast<double>(i));
    }
    case json::value_t::number_float:
      return tinygltf::Value(j.get<double>());
    case json::value_t::string:
      return tinygltf::Value(j.get<std::string>());
    case json::value_t::array: {
      tinygltf::Value::Array a;
      for (const json& e : j) a.push_back(ToValue(e));
      return tinygltf::Value(std::move(a));
    }
    case json::value_t::object: {
      tinygltf::Value::Object o;
      for (const auto& [k, v] : j.items()) o.emplace(k, ToValue(v));
      return tinygltf::Value(std::move(o));
    }
    default:
      return tinygltf::Value();
  }
}

// sRGB component (0..1) to linear: glTF colour factors are linear.
double Linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// The colour of a tag: a hue from a fixed hash (FNV-1a) of its value, so the same tag has the
// same colour in every export, whatever other tags the selection holds.
std::array<double, 4> TagColour(const std::string& tag) {
  uint64_t h = 14695981039346656037ull;
  for (unsigned char c : tag) h = (h ^ c) * 1099511628211ull;
  const double hue = static_cast<double>(h % 3600) / 600.0;  // sextant of the colour wheel
  const double s = 0.55, v = 0.85;
  const double f = hue - std::floor(hue);
  const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  std::array<double, 3> rgb;
  switch (static_cast<int>(hue)) {
    case 0:
      rgb = {v, t, p};
      break;
    case 1:
      rgb = {q, v, p};
      break;
    case 2:
      rgb = {p, v, t};
      break;
    case 3:
      rgb = {p, q, v};
      break;
    case 4:
      rgb = {t, p, v};
      break;
    default:
      rgb = {v, p, q};
      break;
  }
  return {Linear(rgb[0]), Linear(rgb[1]), Linear(rgb[2]), 1.0};
}

// One primitive's triangles: the visible ones of one tag (or untagged), or the invisible ones.
struct Group {
  int32_t key = kNoTag;  // tag index, kNoTag, or kHiddenGroup
  std::vector<uint32_t> triangles;
};

std::vector<Group> GroupTriangles(const Tin& tin, const MeshSelection& s) {
  std::map<int32_t, std::vector<uint32_t>> by_key;
  for (uint32_t t : s.triangles) {
    const TinTriangle& tri = tin.triangles[t];
    by_key[tri.visible ? tri.tag : kHiddenGroup].push_back(t);
  }
  std::vector<Group> groups;
  // Tags first in tag order, then untagged, then invisible.
  for (auto& [key, tris] : by_key)
    if (key >= 0) groups.push_back({key, std::move(tris)});
  for (int32_t key : {kNoTag, kHiddenGroup})
    if (auto it = by_key.find(key); it != by_key.end()) groups.push_back({key, it->second});
  return groups;
}

// The binary chunk being built, and views into it. Every view starts on an 8-byte boundary,
// which EXT_structural_metadata asks of its property views and covers glTF's 4-byte rule.
class BufferBuilder {
 public:
  explicit BufferBuilder(tinygltf::Model& model) : model_(model) {}

  int AddView(const std::string& bytes, int target) {
    while (data_.size() % 8 != 0) data_.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data_.size();
    view.byteLength = bytes.size();
    view.target = target;
    data_.insert(data_.end(), bytes.begin(), bytes.end());
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  int AddAccessor(int view, int component_type, int type, size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component_type;
    a.type = type;
    a.count = count;
    model_.accessors.push_back(a);
    return static_cast<int>(model_.accessors.size() - 1);
  }

  std::vector<unsigned char> Take() {
    while (data_.size() % 8 != 0) data_.push_back(0);
    return std::move(data_);
  }

 private:
  tinygltf::Model& model_;
  std::vector<unsigned char> data_;
};

template <typename T>
std::string Bytes(const std::vector<T>& values) {
  BinaryOut out;
  out.Reserve(values.size() * sizeof(T));
  for (T v : values) out.Put(v);
  return std::move(out.bytes());
}

// Area-weighted vertex normals in the ENU frame, per selected vertex.
std::vector<std::array<double, 3>> VertexNormals(const Tin& tin, const MeshSelection& s,
                                                 const LocalFrame& frame) {
  std::vector<std::array<double, 3>> n(s.vertices.size(), {0, 0, 0});
  for (uint32_t t : s.triangles) {
    const auto& tri = tin.triangles[t];
    const auto& a = frame.enu[static_cast<size_t>(s.output_index[tri.v[0]])];
    const auto& b = frame.enu[static_cast<size_t>(s.output_index[tri.v[1]])];
    const auto& c = frame.enu[static_cast<size_t>(s.output_index[tri.v[2]])];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const std::array<double, 3> cross = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                         u[0] * w[1] - u[1] * w[0]};
    for (uint32_t v : tri.v)
      for (int k = 0; k < 3; ++k) n[static_cast<size_t>(s.output_index[v])][k] += cross[k];
  }
  for (auto& v : n) {
    const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v = length > 0 ? std::array<double, 3>{v[0] / length, v[1] / length, v[2] / length}
                   : std::array<double, 3>{0, 0, 1};
  }
  return n;
}

// A primitive's vertex and index data before it goes into the buffer.
struct PrimitiveData {
  std::vector<float> positions;  // x y z on glTF axes
  std::vector<float> normals;
  std::vector<float> feature_ids;  // empty without features
  std::vector<uint32_t> indices;
  size_t feature_count = 0;  // distinct non-null feature ids
};

// Maps (selected vertex, feature) to a primitive's vertex. Most vertices meet one feature only,
// so the first pairing of each vertex sits in flat arrays and only the vertices where features
// meet go to a hash map. Reused from primitive to primitive: Reset clears only what was used.
class VertexSplitter {
 public:
  explicit VertexSplitter(size_t vertices) : first_(vertices, kNone), first_feature_(vertices) {}

  // The primitive vertex of (v, feature), and whether it is new.
  std::pair<uint32_t, bool> Find(uint32_t v, uint32_t feature) {
    if (first_[v] == kNone) {
      first_[v] = next_, first_feature_[v] = feature;
      touched_.push_back(v);
      return {next_++, true};
    }
    if (first_feature_[v] == feature) return {first_[v], false};
    auto [it, added] = more_.try_emplace((uint64_t{v} << 32) | feature, next_);
    if (added) ++next_;
    return {it->second, added};
  }

  void Reset() {
    for (uint32_t v : touched_) first_[v] = kNone;
    touched_.clear();
    more_.clear();
    next_ = 0;
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  std::vector<uint32_t> first_, first_feature_;
  std::vector<uint32_t> touched_;
  std::unordered_map<uint64_t, uint32_t> more_;
  uint32_t next_ = 0;
};

PrimitiveData BuildPrimitive(const Tin& tin, const MeshSelection& s, const LocalFrame& frame,
                             const std::vector<std::array<double, 3>>& normals,
                             const GlbContent& content, const Group& group,
                             VertexSplitter& splitter) {
  const bool with_features = !content.triangle_feature.empty();
  const uint32_t null_id = static_cast<uint32_t>(content.features.size());
  PrimitiveData p;
  p.indices.reserve(group.triangles.size() * 3);
  std::vector<uint8_t> seen(content.features.size(), 0);
  splitter.Reset();
  for (uint32_t t : group.triangles) {
    uint32_t feature = null_id;
    if (with_features && content.triangle_feature[t] != kNoFeature) {
      feature = static_cast<uint32_t>(content.triangle_feature[t]);
      if (!seen[feature]) seen[feature] = 1, ++p.feature_count;
    }
    for (uint32_t v : tin.triangles[t].v) {
      const auto out = static_cast<uint32_t>(s.output_index[v]);
      const auto [index, added] = splitter.Find(out, with_features ? feature : 0);
      if (added) {
        const auto& e = frame.enu[out];
        const auto& n = normals[out];
        // glTF: y up, right-handed; east, up, -north.
        p.positions.insert(p.positions.end(), {static_cast<float>(e[0]), static_cast<float>(e[2]),
                                               static_cast<float>(-e[1])});
        p.normals.insert(p.normals.end(), {static_cast<float>(n[0]), static_cast<float>(n[2]),
                                           static_cast<float>(-n[1])});
        if (with_features) p.feature_ids.push_back(static_cast<float>(feature));
      }
      p.indices.push_back(index);
    }
  }
  return p;
}

// Vertex-cache order for the indices, then vertices renumbered in first-use order (meshopt's
// vertex fetch remap), applied to every attribute. meshopt's FIFO optimiser rather than its
// best one: it takes about a third of the time, and a TIN read in store order (triangles
// bucketed by block) already has most of the locality the better optimiser would add, so the
// GLB stays within the 1.5x of the OBJ writer's time.
void Optimise(PrimitiveData& p) {
  const size_t vertex_count = p.positions.size() / 3;
  constexpr unsigned kFifoCacheSize = 16;  // below every GPU's post-transform cache
  meshopt_optimizeVertexCacheFifo(p.indices.data(), p.indices.data(), p.indices.size(),
                                  vertex_count, kFifoCacheSize);
  std::vector<unsigned int> remap(vertex_count);
  const size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), p.indices.data(),
                                                       p.indices.size(), vertex_count);
  meshopt_remapIndexBuffer(p.indices.data(), p.indices.data(), p.indices.size(), remap.data());
  auto apply = [&](std::vector<float>& values, size_t width) {
    if (values.empty()) return;
    std::vector<float> out(used * width);
    meshopt_remapVertexBuffer(out.data(), values.data(), vertex_count, width * sizeof(float),
                              remap.data());
    values = std::move(out);
  };
  apply(p.positions, 3);
  apply(p.normals, 3);
  apply(p.feature_ids, 1);
}

tinygltf::Material GroupMaterial(const Tin& tin, int32_t key) {
  tinygltf::Material m;
  m.doubleSided = true;  // terrain is looked at from below too (cuts, tunnels, the underside)
  m.pbrMetallicRoughness.metallicFactor = 0;
  m.pbrMetallicRoughness.roughnessFactor = 1;
  std::array<double, 4> colour{};
  if (key >= 0) {
    m.name = tin.tags[static_cast<size_t>(key)];
    colour = TagColour(m.name);
  } else if (key == kNoTag) {
    m.name = "untagged";
    colour = {Linear(0.8), Linear(0.8), Linear(0.8), 1.0};
  } else {
    m.name = "invisible";
    colour = {Linear(0.5), Linear(0.5), Linear(0.5), 0.35};
    m.alphaMode = "BLEND";
  }
  m.pbrMetallicRoughness.baseColorFactor.assign(colour.begin(), colour.end());
  m.extras = ToValue(
      json{{"tinbase",
            {{"tag", key >= 0 ? json(m.name) : json(nullptr)}, {"visible", key != kHiddenGroup}}}});
  return m;
}

void AddPrimitive(tinygltf::Model& model, BufferBuilder& buffer, PrimitiveData& p, int material,
                  bool with_features, size_t table_rows) {
  const size_t vertex_count = p.positions.size() / 3;
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.material = material;

  const int pos_view = buffer.AddView(Bytes(p.positions), kArrayBuffer);
  const int pos =
      buffer.AddAccessor(pos_view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertex_count);
  // glTF requires POSITION's bounds, exactly as the float values are.
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < p.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], static_cast<double>(p.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], static_cast<double>(p.positions[i]));
  }
  model.accessors[pos].minValues.assign(lo.begin(), lo.end());
  model.accessors[pos].maxValues.assign(hi.begin(), hi.end());
  prim.attributes["POSITION"] = pos;
  prim.attributes["NORMAL"] =
      buffer.AddAccessor(buffer.AddView(Bytes(p.normals), kArrayBuffer),
                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertex_count);

  if (vertex_count <= std::numeric_limits<uint16_t>::max()) {
    std::vector<uint16_t> narrow(p.indices.begin(), p.indices.end());
    prim.indices = buffer.AddAccessor(buffer.AddView(Bytes(narrow), kElementArrayBuffer),
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                      narrow.size());
  } else {
    prim.indices = buffer.AddAccessor(buffer.AddView(Bytes(p.indices), kElementArrayBuffer),
                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                      p.indices.size());
  }

  if (with_features && p.feature_count > 0) {
    prim.attributes["_FEATURE_ID_0"] =
        buffer.AddAccessor(buffer.AddView(Bytes(p.feature_ids), kArrayBuffer),
                           TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, vertex_count);
    const json ext = {{"featureIds",
                       {{{"featureCount", p.feature_count},
                         {"attribute", 0},
                         {"propertyTable", 0},
                         {"nullFeatureId", table_rows},
                         {"label", "feature"}}}}};
    prim.extensions["EXT_mesh_features"] = ToValue(ext);
  }
  model.meshes[0].primitives.push_back(std::move(prim));
}

// A property id: [A-Za-z_][A-Za-z0-9_]*, distinct from those taken.
std::string PropertyId(const std::string& key, std::set<std::string>& taken) {
  std::string id = key.empty() ? "_" : key;
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  if (std::isdigit(static_cast<unsigned char>(id[0]))) id = "_" + id;
  std::string unique = id;
  for (int k = 2; taken.count(unique) > 0; ++k) unique = id + "_" + std::to_string(k);
  taken.insert(unique);
  return unique;
}

// A STRING property's two views: the UTF-8 bytes and the UINT32 offsets (count + 1).
json StringProperty(BufferBuilder& buffer, const std::vector<std::string>& values) {
  std::string bytes;
  std::vector<uint32_t> offsets{0};
  for (const std::string& v : values) {
    bytes += v;
    offsets.push_back(static_cast<uint32_t>(bytes.size()));
  }
  // A view must not be empty; an all-empty column still needs its byte view.
  if (bytes.empty()) bytes.push_back('\0');
  return {{"values", buffer.AddView(bytes, 0)},
          {"stringOffsets", buffer.AddView(Bytes(offsets), 0)}};
}

// EXT_structural_metadata: the schema (class "feature", enum "featureMode") and the property
// table of `features`, its columns in the buffer.
json StructuralMetadata(BufferBuilder& buffer, const std::vector<ExportFeature>& features) {
  json class_props = json::object();
  json table_props = json::object();
  std::set<std::string> taken = {"id", "mode", "tag"};

  std::vector<int64_t> ids;
  std::vector<uint8_t> modes;
  std::vector<std::string> tags;
  for (const ExportFeature& f : features) {
    ids.push_back(f.id);
    modes.push_back(static_cast<uint8_t>(f.mode));
    tags.push_back(f.tag.value_or(""));
  }
  class_props["id"] = {{"type", "SCALAR"},
                       {"componentType", "INT64"},
                       {"required", true},
                       {"description", "The feature's id in the store"}};
  table_props["id"] = {{"values", buffer.AddView(Bytes(ids), 0)}};
  class_props["mode"] = {{"type", "ENUM"}, {"enumType", "featureMode"}, {"required", true}};
  table_props["mode"] = {{"values", buffer.AddView(Bytes(modes), 0)}};
  class_props["tag"] = {{"type", "STRING"}, {"noData", ""}};
  table_props["tag"] = StringProperty(buffer, tags);

  std::set<std::string> keys;
  for (const ExportFeature& f : features)
    if (f.attributes.is_object())
      for (const auto& [k, v] : f.attributes.items()) keys.insert(k);
  for (const std::string& key : keys) {
    const std::string id = PropertyId(key, taken);
    const bool numeric = std::all_of(features.begin(), features.end(), [&](const auto& f) {
      return f.attributes.is_object() && f.attributes.contains(key) &&
             f.attributes[key].is_number();
    });
    if (numeric) {
      std::vector<double> values;
      for (const ExportFeature& f : features) values.push_back(f.attributes[key].get<double>());
      class_props[id] = {{"name", key}, {"type", "SCALAR"}, {"componentType", "FLOAT64"}};
      table_props[id] = {{"values", buffer.AddView(Bytes(values), 0)}};
      continue;
    }
    std::vector<std::string> values;
    for (const ExportFeature& f : features) {
      const bool has = f.attributes.is_object() && f.attributes.contains(key);
      const json& v = has ? f.attributes[key] : json();
      values.push_back(!has || v.is_null() ? "" : v.is_string() ? v.get<std::string>() : v.dump());
    }
    class_props[id] = {{"name", key}, {"type", "STRING"}, {"noData", ""}};
    table_props[id] = StringProperty(buffer, values);
  }

  json mode_values = json::array();
  for (FeatureMode mode : kFeatureModes)
    mode_values.push_back({{"name", FeatureModeName(mode)}, {"value", static_cast<int>(mode)}});
  const json schema = {
      {"id", "tinbase"},
      {"classes",
       {{"feature",
         {{"name", "Feature"},
          {"description", "A tinbase feature: the polygon that gave the triangle its tag"},
          {"properties", class_props}}}}},
      {"enums", {{"featureMode", {{"valueType", "UINT8"}, {"values", mode_values}}}}}};
  return {{"schema", schema},
          {"propertyTables",
           {{{"name", "features"},
             {"class", "feature"},
             {"count", features.size()},
             {"properties", table_props}}}}};
}

json AssetExtras(const Crs* crs, const LocalFrame& frame) {
  json origin = {{"x", frame.x0}, {"y", frame.y0}, {"z", frame.z0}};
  json t = {{"axes", "x east, y up, z south (-north); metres"}};
  if (frame.geodetic) {
    t["frame"] = "ENU";
    origin["latitude"] = frame.latitude;
    origin["longitude"] = frame.longitude;
    origin["height"] = frame.height;
    t["geographic_crs"] = frame.geographic_crs;
    t["ellipsoid"] = {{"semi_major", frame.semi_major},
                      {"inverse_flattening", frame.inverse_flattening}};
  } else {
    t["frame"] = "store axes shifted to the origin (no CRS)";
    t["axes"] = "x = store x, y = store z, z = -store y; store units";
  }
  t["origin"] = origin;
  // Without a CRS there are no crs keys at all: tinygltf drops JSON nulls.
  if (crs != nullptr) {
    t["crs"] = crs->Label();
    t["crs_wkt"] = OneLineWkt(*crs);
    if (auto epsg = crs->Epsg()) t["epsg"] = *epsg;
  }
  return {{"tinbase", t}};
}

}  // namespace

Status WriteGlb(const Tin& tin, const Crs* crs, const MeshSelection& s, const GlbContent& content,
                const std::string& path) {
  if (s.triangles.empty()) return Status::InvalidArgument(path + ": no triangles to write");
  if (!content.triangle_feature.empty() && content.triangle_feature.size() != tin.triangles.size())
    return Status::InvalidArgument(path + ": " + std::to_string(content.triangle_feature.size()) +
                                   " feature ids for " + std::to_string(tin.triangles.size()) +
                                   " triangles");
  TB_ASSIGN_OR_RETURN(LocalFrame frame, ToLocalFrame(tin, crs, s));
  const std::vector<std::array<double, 3>> normals = VertexNormals(tin, s, frame);
  const bool with_features = !content.triangle_feature.empty() && !content.features.empty();

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "tinbase";
  model.asset.extras = ToValue(AssetExtras(crs, frame));
  model.meshes.emplace_back();
  model.meshes[0].name = "surface";
  BufferBuilder buffer(model);
  bool any_features = false;
  VertexSplitter splitter(s.vertices.size());
  for (const Group& group : GroupTriangles(tin, s)) {
    PrimitiveData p = BuildPrimitive(tin, s, frame, normals, content, group, splitter);
    Optimise(p);
    model.materials.push_back(GroupMaterial(tin, group.key));
    any_features = any_features || (with_features && p.feature_count > 0);
    AddPrimitive(model, buffer, p, static_cast<int>(model.materials.size() - 1), with_features,
                 content.features.size());
  }
  if (any_features) {
    model.extensions["EXT_structural_metadata"] =
        ToValue(StructuralMetadata(buffer, content.features));
    model.extensionsUsed = {"EXT_mesh_features", "EXT_structural_metadata"};
  }
  tinygltf::Buffer data;
  data.data = buffer.Take();
  model.buffers.push_back(std::move(data));
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "surface";
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Status::IOError(path + ": cannot open for writing");
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, file, /*prettyPrint=*/false, /*writeBinary=*/true))
    return Status::IOError(path + ": tinygltf could not write the GLB");
  file.close();
  if (!file) return Status::IOError(path + ": write failed");
  return Status::Ok();
}

}  // namespace tinbase
