// The JSON of the measures.
#include "db/query/measure_json.h"

namespace tinbase {

namespace {

nlohmann::json SumJson(const AreaSum& s) {
  return {{"triangles", s.triangles}, {"plan_m2", s.plan}, {"surface_m2", s.surface}};
}

template <typename T>
nlohmann::json Nullable(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json AreaJson(const MeasureSource& source, const AreaReport& report) {
  nlohmann::json j = {{"surface", source.surface.name},
                      {"crs", source.crs ? nlohmann::json(source.crs->Label()) : nullptr},
                      {"plan_area", report.geodesic ? "geodesic" : "map plane"},
                      {"total", SumJson(report.total)},
                      {"tags", nlohmann::json::array()}};
  for (const TagArea& t : report.tags) {
    nlohmann::json row = SumJson(t.area);
    row["tag"] = Nullable(t.tag);
    j["tags"].push_back(row);
  }
  return j;
}

nlohmann::json VolumeJson(const MeasureSource& source, double level, bool inside_polygon,
                          const VolumeReport& volume) {
  const SplitMeasure& s = volume.split;
  return {{"surface", source.surface.name},   {"level", level},
          {"inside_polygon", inside_polygon}, {"above_m3", s.above_volume},
          {"below_m3", s.below_volume},       {"above_area_m2", s.above_area},
          {"below_area_m2", s.below_area},    {"plan_area_m2", volume.plan_area}};
}

nlohmann::json SlopeJson(const MeasureSource& source, const TriangleSlope& slope) {
  const Tin& tin = source.part.tin;
  const int32_t tag = tin.triangles[slope.triangle].tag;
  const bool tagged = tag >= 0 && static_cast<size_t>(tag) < tin.tags.size();
  return {{"triangle", source.part.triangle_ids[slope.triangle]},
          {"slope_deg", slope.slope_degrees},
          {"aspect_deg", Nullable(slope.aspect_degrees)},
          {"tag", tagged ? nlohmann::json(tin.tags[static_cast<size_t>(tag)]) : nullptr}};
}

}  // namespace tinbase
