// The store a test writes to: a file in the test's temporary folder, or, when CTest runs the
// test a second time with TINBASE_TEST_BACKEND=postgresql (tests/CMakeLists.txt, "on both
// backends"), a schema of the test server that no other test uses. Tests that go through the
// storage seam take their store from here, so one test checks both backends.
#pragma once

#include <cstdlib>
#include <map>
#include <mutex>
#include <string>

#include "tests/support/postgres_support.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// True when this run of the test is its PostgreSQL run.
inline bool OnPostgres() {
  const char* backend = std::getenv("TINBASE_TEST_BACKEND");
  return backend != nullptr && std::string(backend) == "postgresql";
}

// The store target for `name` in `dir`: the same target each time it is asked for (a test
// creates, opens and checks one store by one name).
inline std::string StoreTarget(const TempDir& dir, const std::string& name) {
  const std::string path = dir.Path(name);
  if (!OnPostgres()) return path;
  static std::mutex mutex;
  static std::map<std::string, std::string> targets;
  std::lock_guard<std::mutex> lock(mutex);
  auto [it, fresh] = targets.try_emplace(path);
  if (fresh) it->second = FreshPostgresStore("s");
  return it->second;
}

}  // namespace tinbase::testing
