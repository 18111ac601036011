// The JSON of a profile.
#include "db/query/profile_json.h"

namespace tinbase {

nlohmann::json ProfileJson(const SurfaceProfile& p, const std::string& surface) {
  nlohmann::json stations = nlohmann::json::array(), stretches = nlohmann::json::array();
  for (const Station& s : p.stations)
    stations.push_back({{"distance", s.distance},
                        {"x", s.x},
                        {"y", s.y},
                        {"z", s.z},
                        {"kind", StationKindName(s.kind)}});
  for (size_t i = 0; i < p.stretches.size(); ++i) {
    const ProfileStretch& r = p.stretches[i];
    stretches.push_back({{"from", p.stations[i].distance},
                         {"to", p.stations[i + 1].distance},
                         {"triangle", r.triangle},
                         {"visible", r.visible},
                         {"tag", r.tag ? nlohmann::json(*r.tag) : nlohmann::json(nullptr)}});
  }
  return {{"surface", surface},
          {"length", p.length()},
          {"stations", stations},
          {"stretches", stretches}};
}

}  // namespace tinbase
