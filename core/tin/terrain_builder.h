// Terrain builder: one entry point that builds a terrain TIN from a grid DEM by a chosen method
// (greedy insertion, very important points, the binary triangle tree, or edge collapse of the
// full grid triangulation), for the code that builds surfaces (db/surface_builder) and the CLI.
// The method is an enum: the CLI parses the user's text once (ParseTerrainMethod) and nothing
// past it compares method names.
//
// Each method's own header has its contract: greedy_builder.h, vip_builder.h, rtin_builder.h,
// edge_collapse.h. What differs for the caller is whether the result is Delaunay: greedy and VIP
// triangulate their points with CGAL's Delaunay triangulation, so the surface is stored as
// `delaunay` and the checker holds it to the local Delaunay test (docs/design.md, "Invariants",
// invariant 5); an RTIN is not Delaunay (on square cells a conforming binary tree happens to pass
// the empty-circle test up to its many co-circular ties, but on rectangular cells it fails, and
// nothing in its construction looks at circles), nor is an edge-collapsed TIN, so both are stored
// as `free`.
// Thread-safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "core/base/status.h"
#include "core/raster/grid.h"
#include "core/tin/edge_collapse.h"
#include "core/tin/tin.h"

namespace tinbase {

enum class TerrainMethod { kGreedy, kVip, kRtin, kCollapse };

inline constexpr std::array<TerrainMethod, 4> kTerrainMethods = {
    TerrainMethod::kGreedy, TerrainMethod::kVip, TerrainMethod::kRtin, TerrainMethod::kCollapse};

// The canonical spelling, as the CLI takes it and `surfaces.method` records it: "greedy", "vip",
// "rtin" or "collapse".
const char* TerrainMethodName(TerrainMethod method);
// The method `name` spells (exactly). InvalidArgument "unknown TIN method 'x' (expected greedy,
// vip, rtin or collapse)" otherwise.
Result<TerrainMethod> ParseTerrainMethod(std::string_view name);
// True for the methods whose result is a Delaunay triangulation (greedy, VIP).
bool IsDelaunayMethod(TerrainMethod method);

struct TerrainBuildOptions {
  TerrainMethod method = TerrainMethod::kGreedy;
  double tolerance = 1.0;         // metres: the error bound of greedy and RTIN; unused otherwise
  double threshold = 1.0;         // metres: VIP's significance threshold; unused otherwise
  int64_t max_points = 0;         // greedy and VIP: 0 or >= 4; RTIN has no point budget: must be 0
  CollapseOptions collapse = {};  // collapse: the face budget and strategy; unused otherwise
};

struct TerrainBuildReport {
  TerrainMethod method = TerrainMethod::kGreedy;
  bool delaunay = true;  // store as a `delaunay` surface if true, else as `free`
  // True when every valid cell is within `tolerance`: always for RTIN, for greedy when its
  // max_points did not stop it first (read from its measured error); false for VIP, which has
  // no tolerance.
  bool within_tolerance = false;
  double max_error = 0;  // largest |TIN - DEM| over valid cells
  double rms_error = 0;
  int64_t points = 0;
  int64_t triangles = 0;
  CollapseReport collapse;  // collapse: the whole report of CollapseToFaceBudget
};

// Returns the method's TIN and fills `report` when given. InvalidArgument with the method's own
// message for what it rejects, for a max_points other than 0 with RTIN, and for collapse of a
// DEM with no 2 x 2 cells of data.
Result<Tin> BuildTerrainTin(const Grid& dem, const TerrainBuildOptions& options,
                            TerrainBuildReport* report = nullptr);

}  // namespace tinbase
