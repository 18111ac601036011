// Negotiating a terrain tile's extensions through Accept.
#include "service/terrain_negotiation.h"

#include "service/header_lists.h"

namespace tinbase::service {

namespace {

constexpr const char* kQuantizedMesh = "application/vnd.quantized-mesh";

void AddByName(const std::string& name, TileExtensions* set) {
  if (name == "octvertexnormals") set->normals = true;
  if (name == "watermask") set->water_mask = true;
  if (name == "metadata") set->metadata = true;
}

}  // namespace

TileExtensions RequestedTileExtensions(const httplib::Request& req) {
  TileExtensions asked;
  if (!req.has_header("Accept")) return asked;
  for (const HeaderElement& e : ParseHeaderList(req.get_header_value("Accept"))) {
    if (e.value != kQuantizedMesh || e.q <= 0) continue;
    const auto it = e.params.find("extensions");
    if (it == e.params.end()) continue;
    const std::string& list = it->second;
    size_t start = 0;
    while (start <= list.size()) {
      size_t end = list.find('-', start);
      if (end == std::string::npos) end = list.size();
      AddByName(list.substr(start, end - start), &asked);
      start = end + 1;
    }
  }
  return asked;
}

TileExtensions CommonTileExtensions(const TileExtensions& a, const TileExtensions& b) {
  TileExtensions both;
  both.normals = a.normals && b.normals;
  both.water_mask = a.water_mask && b.water_mask;
  both.metadata = a.metadata && b.metadata;
  return both;
}

std::string TerrainContentType(const TileExtensions& sent) {
  std::string names;
  for (const auto& [on, name] :
       {std::pair{sent.normals, "octvertexnormals"}, std::pair{sent.water_mask, "watermask"},
        std::pair{sent.metadata, "metadata"}}) {
    if (!on) continue;
    if (!names.empty()) names += '-';
    names += name;
  }
  return names.empty() ? kQuantizedMesh : std::string(kQuantizedMesh) + ";extensions=" + names;
}

std::string TileExtensionsCode(const TileExtensions& set) {
  std::string code;
  if (set.normals) code += 'n';
  if (set.water_mask) code += 'w';
  if (set.metadata) code += 'm';
  return code.empty() ? "0" : code;
}

}  // namespace tinbase::service
