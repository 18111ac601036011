#include "core/tin/grid_triangulation.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry/predicates.h"

namespace tinbase {
namespace {

// Squares are indexed by their north-west cell: square (c, r) joins cells (c, r), (c+1, r),
// (c, r+1), (c+1, r+1).
class SquareSet {
 public:
  explicit SquareSet(const Grid& grid)
      : w_(grid.geometry.width - 1),
        h_(grid.geometry.height - 1),
        kept_(static_cast<size_t>(std::max<int64_t>(0, w_) * std::max<int64_t>(0, h_)), false) {
    for (int64_t r = 0; r < h_; ++r) {
      for (int64_t c = 0; c < w_; ++c) {
        kept_[Index(c, r)] = grid.IsValid(c, r) && grid.IsValid(c + 1, r) &&
                             grid.IsValid(c, r + 1) && grid.IsValid(c + 1, r + 1);
      }
    }
  }

  bool Has(int64_t c, int64_t r) const {
    return c >= 0 && r >= 0 && c < w_ && r < h_ && kept_[Index(c, r)];
  }
  int64_t width() const { return w_; }
  int64_t height() const { return h_; }

  // Drops squares until no cell centre is the only shared point of two squares. Around a centre
  // the four squares in turn are NW, NE, SE, SW; two present and diagonal to each other is the
  // one non-manifold case. Dropping the SE or SW one (the later in row order) can create that case
  // at its other corners, so repeat until nothing changes; squares only disappear, so it ends.
  void DropPinchedSquares() {
    bool changed = true;
    while (changed) {
      changed = false;
      for (int64_t r = 0; r <= h_; ++r) {
        for (int64_t c = 0; c <= w_; ++c) {
          const bool nw = Has(c - 1, r - 1), ne = Has(c, r - 1);
          const bool sw = Has(c - 1, r), se = Has(c, r);
          if (nw + ne + sw + se != 2) continue;
          if (nw && se) {
            kept_[Index(c, r)] = false;
            changed = true;
          } else if (ne && sw) {
            kept_[Index(c - 1, r)] = false;
            changed = true;
          }
        }
      }
    }
  }

 private:
  size_t Index(int64_t c, int64_t r) const { return static_cast<size_t>(r * w_ + c); }
  int64_t w_, h_;
  std::vector<bool> kept_;
};

}  // namespace

Tin GridTriangulation(const Grid& grid) {
  Tin tin;
  const GridGeometry& g = grid.geometry;
  if (g.width < 2 || g.height < 2) return tin;
  SquareSet squares(grid);
  squares.DropPinchedSquares();

  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> vertex_of(static_cast<size_t>(g.CellCount()), kUnused);
  const auto cell = [&](int64_t c, int64_t r) { return static_cast<size_t>(r * g.width + c); };
  for (int64_t r = 0; r < g.height; ++r) {
    for (int64_t c = 0; c < g.width; ++c) {
      const bool used = squares.Has(c - 1, r - 1) || squares.Has(c, r - 1) ||
                        squares.Has(c - 1, r) || squares.Has(c, r);
      if (!used) continue;
      vertex_of[cell(c, r)] = static_cast<uint32_t>(tin.vertices.size());
      tin.vertices.push_back({g.CellCenterX(c), g.CellCenterY(r), grid.At(c, r), VertexKind::kDem});
    }
  }

  const auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    const TinVertex &pa = tin.vertices[a], &pb = tin.vertices[b], &pc = tin.vertices[c];
    const int turn = Orientation({pa.x, pa.y}, {pb.x, pb.y}, {pc.x, pc.y});
    assert(turn != 0);
    TinTriangle t;
    t.v = turn > 0 ? std::array<uint32_t, 3>{a, b, c} : std::array<uint32_t, 3>{a, c, b};
    tin.triangles.push_back(t);
  };
  for (int64_t r = 0; r < squares.height(); ++r) {
    for (int64_t c = 0; c < squares.width(); ++c) {
      if (!squares.Has(c, r)) continue;
      const uint32_t nw = vertex_of[cell(c, r)], ne = vertex_of[cell(c + 1, r)];
      const uint32_t sw = vertex_of[cell(c, r + 1)], se = vertex_of[cell(c + 1, r + 1)];
      const double d_nwse = std::fabs(tin.vertices[nw].z - tin.vertices[se].z);
      const double d_nesw = std::fabs(tin.vertices[ne].z - tin.vertices[sw].z);
      if (d_nwse <= d_nesw) {
        add(nw, sw, se);
        add(nw, se, ne);
      } else {
        add(nw, sw, ne);
        add(ne, sw, se);
      }
    }
  }
  [[maybe_unused]] const bool linked = LinkNeighbours(tin);
  assert(linked);
  return tin;
}

}  // namespace tinbase
