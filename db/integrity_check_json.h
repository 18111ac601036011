// The JSON of an integrity check (db/integrity_check.h): what `tinbase check --json` prints and
// what the SQL function `tinbase_check` answers, written in one place so the two cannot drift
// apart. Thread-safety: pure function.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "db/integrity_check.h"

namespace tinbase {

// {"ok": problems.empty(), "problems": [{code, surface, triangle (null when none), message}]},
// in the checker's order.
nlohmann::json CheckJson(const std::vector<Problem>& problems);

}  // namespace tinbase
