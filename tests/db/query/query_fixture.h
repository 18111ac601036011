// A store holding one generated Tin, for the query tests: made through the library's own write
// path, and checked intact before any query runs. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/tin/tin.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase::testing {

struct StoredSurface {
  std::unique_ptr<Store> store;
  SurfaceInfo info;
  LoadedSurface loaded;  // the rows as stored, with their ids
};

// Writes `tin` as surface `name` of a new store at `path` (CRS EPSG:32632).
inline Result<StoredSurface> StoreSurface(const std::string& path, const std::string& name,
                                          const Tin& tin) {
  StoredSurface out;
  TB_ASSIGN_OR_RETURN(out.store, Store::Create(path, "EPSG:32632"));
  TB_ASSIGN_OR_RETURN(auto tx, out.store->BeginWrite());
  SurfaceInfo spec;
  spec.name = name;
  spec.kind = SurfaceKind::kFree;
  spec.method = "test";
  TB_ASSIGN_OR_RETURN(out.info, SurfaceStore(*out.store).Create(spec, tin));
  TB_RETURN_IF_ERROR(tx->Commit());
  TB_ASSIGN_OR_RETURN(out.loaded, SurfaceStore(*out.store).Load(out.info));
  ExpectStoreIntact(*out.store);
  return out;
}

// A plane whose z is known everywhere: the profile and location tests compare with it.
inline double PlaneZ(double x, double y) { return 0.5 * x - 0.25 * y + 100; }

}  // namespace tinbase::testing
