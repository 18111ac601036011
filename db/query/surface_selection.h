// Surface selection: the part of a stored surface that an export or a query asks for (a window,
// the inside of one feature, the visible triangles, one tag), as a compact LoadedSurface.
//
// Every exporter and every "triangles of ..." query goes through SelectSurface, so `--bbox`,
// `--feature`, `--visible-only` and `--tag` mean the same thing everywhere. A window reads only
// the blocks under it and the triangles reached from them across the window (docs/design.md,
// "Point location": triangles are bucketed by centroid, and a large triangle can meet a window
// whose blocks do not hold its centroid, so the window is grown by walking neighbours).
// Thread-safety: as the Store it reads.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "db/feature_store.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct SurfaceFilter {
  std::optional<Box> bbox;         // triangles that meet this plan-view box (closed)
  int64_t feature = 0;             // 0: all; else the inside of this polygon feature, clipped
  bool visible_only = false;       // leave out invisible triangles
  std::optional<std::string> tag;  // only triangles with this tag value

  // "bbox 1,2,3,4, feature 7, visible only, tag 'granite'"; "everything" when nothing is set.
  std::string Describe() const;
};

// The selected part of `surface`: only the vertices its triangles use; neighbours across the
// selection's edge become kNoNeighbour; vertex_ids and triangle_ids are store ids; triangles and
// vertices in store id order. NotFound naming the surface and the filter when nothing is
// selected; NotFound when `filter.feature` is not a feature of `surface`; InvalidArgument for a
// breakline feature (it has no inside).
Result<LoadedSurface> SelectSurface(Store& store, const SurfaceInfo& surface,
                                    const SurfaceFilter& filter);

// "minx,miny,maxx,maxy" (commas or spaces) → Box. InvalidArgument naming the text when it is not
// four finite numbers with min <= max.
Result<Box> ParseBbox(const std::string& text);

}  // namespace tinbase
