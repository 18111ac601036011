// Grid triangulation: the full-resolution TIN of a grid DEM, each square of four neighbouring
// cell centres split by a diagonal (paper 001's simplest method).
//
// This is the input of edge collapse (paper 002): every valid sample is a vertex, so the
// simplified TIN's error can be measured against the very samples it started from.
// Thread-safety: pure function.
#pragma once

#include "core/raster/grid.h"
#include "core/tin/tin.h"

namespace tinbase {

// The TIN whose vertices are the centres of valid cells (kind kDem, z the cell value) and whose
// triangles split every square of four valid neighbouring centres along the diagonal whose ends
// differ less in z (it follows ridges and valleys; ties take the NW-SE one). Squares touching
// nodata are left out; where that would leave two squares meeting at a single corner (a
// non-manifold vertex, which neither the store's checker nor a halfedge mesh accepts), one of
// them is dropped too. Triangles are counter-clockwise in plan view, neighbours linked. Vertices
// are in row-major cell order; unused valid cells (isolated by nodata) are not vertices. An
// empty Tin when no square is complete.
Tin GridTriangulation(const Grid& grid);

}  // namespace tinbase
