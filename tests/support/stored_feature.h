// A feature as the store holds it, read back through the feature store for the edit tests of the
// CLI and the service (the mode, tag, z source and geometry an edit wrote). Header-only.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "db/feature_store.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase::testing {

// Feature `id` of surface `surface` in the store at `path`, opened read-only; an empty feature
// (and a test failure) when it cannot be read.
inline EditorFeature LoadStoredFeature(const std::string& path, const std::string& surface,
                                       int64_t id) {
  auto store = Store::Open(path, Store::Access::kReadOnly);
  EXPECT_TRUE(store.ok()) << store.status().ToString();
  if (!store.ok()) return {};
  auto info = SurfaceStore(**store).Find(surface);
  EXPECT_TRUE(info.ok()) << info.status().ToString();
  if (!info.ok()) return {};
  auto f = LoadFeature(**store, *info, id);
  EXPECT_TRUE(f.ok()) << f.status().ToString();
  return f.ok() ? *f : EditorFeature{};
}

}  // namespace tinbase::testing
