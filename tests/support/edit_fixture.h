// A store for the tests of the edit path's stages (db/edit/): the Hamersley DEM with a greedy
// surface at 5 m, and local edits that add rings on it, draped on the DEM. Header-only.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "db/dem_store.h"
#include "db/edit/edit_context.h"
#include "db/edit/local_edit.h"
#include "db/mesh_cache.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
inline constexpr double kEditCx = 539300, kEditCy = 7497340, kEditCell = 344.404386931320971;

class EditFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(StoreTarget(dir_, "s.tinbase"), "");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    dems_ = std::make_unique<DemStore>(*store_);
    ASSERT_TRUE(dems_->Import({DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    auto built = BuildSurfaceFromDem(*store_, o);
    ASSERT_TRUE(built.ok()) << built.status().ToString();
    ASSERT_TRUE(ReloadSurface());
  }

  // Closes the store (when `reopen`, opens it again with a fresh DEM store and mesh cache).
  void Close(bool reopen) {
    mesh_.reset();
    dems_.reset();
    store_.reset();
    if (!reopen) return;
    auto store = Store::Open(StoreTarget(dir_, "s.tinbase"));
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    dems_ = std::make_unique<DemStore>(*store_);
    ASSERT_TRUE(ReloadSurface());
  }

  // Reads the surface and DEM rows again (after a write through the polygon editor).
  bool ReloadSurface() {
    auto surface = SurfaceStore(*store_).Find("terrain");
    if (!surface.ok()) return false;
    surface_ = *surface;
    auto dem = dems_->FindById(*surface_.dem);
    if (!dem.ok()) return false;
    dem_ = *dem;
    mesh_ = std::make_unique<MeshCache>(*store_, surface_);
    return true;
  }

  EditContext Context() { return EditContext{*store_, surface_, *dems_, dem_, *mesh_}; }

  // Closed `ring` (last point = first) as a polyline of feature `feature`, z from the DEM (0 off
  // it).
  EditPolyline Drape(const PointList& ring, int64_t feature) {
    EditPolyline line;
    line.closed = true;
    line.feature = feature;
    for (size_t k = 0; k + 1 < ring.size(); ++k) {
      auto z = dems_->Sample(dem_, ring[k].first, ring[k].second);
      line.points.push_back({ring[k].first, ring[k].second, z.ok() ? *z : 0, VertexKind::kRing});
    }
    return line;
  }

  // An in-memory fill feature `id` over `ring` (not stored).
  static EditorFeature FillFeature(int64_t id, const PointList& ring, const std::string& tag) {
    EditorFeature f;
    f.id = id;
    f.label = "feature " + std::to_string(id);
    f.mode = FeatureMode::kFill;
    f.tag = tag;
    Polygon polygon;
    for (size_t k = 0; k + 1 < ring.size(); ++k)
      polygon.shell.push_back({ring[k].first, ring[k].second});
    f.polygons.push_back(polygon);
    return f;
  }

  // A local edit adding `ring` as fill feature `id` to a surface with no other feature.
  LocalEdit AddRing(const PointList& ring, int64_t id, const std::string& tag = "t") {
    LocalEdit edit;
    edit.add.push_back(Drape(ring, id));
    edit.features.push_back(FillFeature(id, ring, tag));
    edit.changed = BoxOf(edit.features.back());
    return edit;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<DemStore> dems_;
  SurfaceInfo surface_;
  DemInfo dem_;
  std::unique_ptr<MeshCache> mesh_;
};

}  // namespace tinbase::testing
