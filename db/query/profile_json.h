// The JSON of a profile (db/query/profile.h): what `tinbase profile --json` prints and what
// `GET /surfaces/{s}/profile` answers, written in one place so the two cannot drift apart.
// Thread-safety: pure function.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "db/query/profile.h"

namespace tinbase {

// {"surface", "length", "stations": [{distance, x, y, z, kind}], "stretches": [{from, to,
// triangle, visible, tag}]}; stretches[i] runs from stations[i] to stations[i + 1].
nlohmann::json ProfileJson(const SurfaceProfile& profile, const std::string& surface);

}  // namespace tinbase
