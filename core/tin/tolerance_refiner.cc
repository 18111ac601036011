#include "core/tin/tolerance_refiner.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <queue>
#include <set>
#include <utility>

#include "core/geometry/predicates.h"
#include "core/tin/cell_cover.h"
#include "core/tin/worst_cell.h"

namespace tinbase {

namespace {

class Refiner {
 public:
  Refiner(Cdt& cdt, CellSource& dem, const RefineOptions& options)
      : cdt_(cdt), dem_(dem), geometry_(dem.geometry()), options_(options) {
    if (options.tile > 0) {
      tiles_across_ = (geometry_.width + options.tile - 1) / options.tile;
      const int64_t tiles_down = (geometry_.height + options.tile - 1) / options.tile;
      queues_.resize(static_cast<size_t>(std::max<int64_t>(1, tiles_across_ * tiles_down)));
    } else {
      queues_.resize(1);
    }
    parallel_ = options.parallel_scans && dem.ConcurrentReads();
  }

  std::vector<uint32_t> Run(std::vector<Cdt::FaceRef> region, RefineReport* report) {
    if (options_.tile > 0) SortByTile(region);
    for (Cdt::FaceRef f : region) Scan(f);
    bool reached = true;
    if (options_.tile <= 0) {
      reached = Drain(queues_[0], 0);
    } else {
      // Passes over the tiles in row order, each inserting what is worse than a level that
      // falls by kPassFactor per pass down to the tolerance: the large faces of the first
      // passes are few, and later passes stay inside a tile and its neighbours, so a streamed
      // DEM is read nearly in order instead of wherever the worst sample of all happens to be.
      constexpr double kPassFactor = 1.5;
      double level = 0;
      for (const auto& queue : queues_)
        if (!queue.empty()) level = std::max(level, queue.top().error);
      for (bool more = level > 0; more && reached;) {
        level = std::max(options_.tolerance, level / kPassFactor);
        for (auto& queue : queues_) {
          reached = Drain(queue, level);
          if (!reached) break;
        }
        more = level > options_.tolerance || std::any_of(queues_.begin(), queues_.end(),
                                                         [](const Queue& q) { return !q.empty(); });
      }
    }
    if (report != nullptr) {
      report->points_added = static_cast<int64_t>(added_.size());
      report->reached = reached;
    }
    return std::move(added_);
  }

 private:
  struct Candidate {
    double error;
    Cdt::FaceRef face;
    uint64_t stamp;
    int64_t col, row;
    bool operator<(const Candidate& o) const { return error < o.error; }
  };
  using Queue = std::priority_queue<Candidate>;
  using Corners = std::array<Cdt::Corner, 3>;

  // Inserts the worst sample of `queue` while it is worse than `level` (0: until the queue is
  // empty). False when max_points stopped it first.
  bool Drain(Queue& queue, double level) {
    while (!queue.empty() && queue.top().error > level) {
      const Candidate worst = queue.top();
      queue.pop();
      if (cdt_.FaceStamp(worst.face) != worst.stamp) continue;  // face changed since its scan
      if (options_.max_points > 0 && static_cast<int64_t>(added_.size()) >= options_.max_points)
        return false;
      const size_t before = cdt_.vertices().size();
      const TinVertex v{geometry_.CellCenterX(worst.col), geometry_.CellCenterY(worst.row),
                        dem_.At(worst.col, worst.row), VertexKind::kDem};
      const uint32_t index = cdt_.InsertVertex(v, worst.face, &incident_);
      if (cdt_.vertices().size() == before) {
        // The cell centre is already a vertex whose z is not the cell's (a ring vertex draped
        // bilinearly, a replace level): the DEM cannot do better there, so stop asking.
        blocked_.insert({worst.col, worst.row});
        Scan(worst.face);
        continue;
      }
      added_.push_back(index);
      ScanAll(incident_);
    }
    return true;
  }

  // Faces in the row order of the tiles holding their first vertex, so the first scan of a
  // streamed DEM reads it in order.
  void SortByTile(std::vector<Cdt::FaceRef>& faces) const {
    const auto first_vertex = [&](size_t i) {
      const TinVertex& v = cdt_.vertices()[cdt_.FaceVertices(faces[i])[0]];
      return std::pair{v.x, v.y};
    };
    std::vector<Cdt::FaceRef> sorted;
    sorted.reserve(faces.size());
    for (size_t i : InTileOrder(geometry_, options_.tile, faces.size(), first_vertex))
      sorted.push_back(faces[i]);
    faces = std::move(sorted);
  }

  Queue& QueueOf(int64_t col, int64_t row) {
    if (options_.tile <= 0) return queues_[0];
    return queues_[static_cast<size_t>((row / options_.tile) * tiles_across_ +
                                       col / options_.tile)];
  }

  // A face about to be scanned: its stamp is taken when it is prepared, in the order the faces
  // are given, so a scan split between two threads stamps and queues as one thread would.
  struct ScanJob {
    Cdt::FaceRef face;
    uint64_t stamp = 0;
    Corners corners;
    CellTriangle cells;
    CellPlane plane;
    WorstCell worst;
  };

  // Gives the face a fresh stamp (invalidating its older queue entries) and queues its worst
  // sample if that is beyond the tolerance.
  void Scan(Cdt::FaceRef face) {
    ScanJob job;
    if (!Prepare(face, &job)) return;
    job.worst = WorstOfFaceSharingRows(job);
    FinishScan(job);
  }

  // Scans the faces one insertion made. When they hold many cells together, they are scanned
  // in parallel, a face per task: on coarse tolerances most insertions split faces of thousands
  // of cells, too small one by one to share by rows (AnyWorstCell) but not together. Each job's
  // result depends on its face alone and the jobs are queued in their given order afterwards, so
  // the result is that of one thread.
  void ScanAll(const std::vector<Cdt::FaceRef>& faces) {
    // Below this, handing faces to other threads costs about what it saves.
    constexpr double kParallelFacesCells = 1 << 10;
    if (!Parallel() || faces.size() < 2) {
      for (Cdt::FaceRef f : faces) Scan(f);
      return;
    }
    jobs_.clear();
    double cells = 0;
    for (Cdt::FaceRef f : faces) {
      ScanJob job;
      if (!Prepare(f, &job)) continue;
      cells += TriangleCells(job.cells);
      jobs_.push_back(job);
    }
    if (cells < kParallelFacesCells || jobs_.size() < 2) {
      for (ScanJob& job : jobs_) job.worst = WorstOfFaceSharingRows(job);
    } else {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, jobs_.size()),
                        [this](const tbb::blocked_range<size_t>& range) {
                          for (size_t i = range.begin(); i != range.end(); ++i)
                            jobs_[i].worst = WorstOfFace(jobs_[i]);
                        });
    }
    for (const ScanJob& job : jobs_) FinishScan(job);
  }

  // Whether scans may be shared: allowed by the options and the DEM, and more than one thread
  // in the arena this runs in.
  bool Parallel() const { return parallel_ && tbb::this_task_arena::max_concurrency() > 1; }

  // Stamps the face and fills `job`; false when the face is not scanned (outside the region, or
  // of zero area).
  bool Prepare(Cdt::FaceRef face, ScanJob* job) {
    job->face = face;
    job->stamp = next_stamp_++;
    cdt_.SetFaceStamp(face, job->stamp);
    job->corners = cdt_.FaceCorners(face);
    const Corners& v = job->corners;
    if (options_.in_region && !options_.in_region({v[0].index, v[1].index, v[2].index}))
      return false;
    job->cells = InCellSpace(v);
    return PlaneOf(job->cells, &job->plane);
  }

  // Queues the job's worst sample if it is beyond the tolerance.
  void FinishScan(const ScanJob& job) {
    const WorstCell& worst = job.worst;
    if (worst.col >= 0) {
      QueueOf(worst.col, worst.row)
          .push(Candidate{worst.error, job.face, job.stamp, worst.col, worst.row});
    }
  }

  // The worst sample the face may insert, its rows shared between threads when it is very large
  // (AnyWorstCell).
  WorstCell WorstOfFaceSharingRows(const ScanJob& job) {
    return Insertable(job, AnyWorstCell(job.cells, job.plane));
  }

  // The worst sample the face may insert, on the calling thread alone: reads the DEM, the
  // blocked cells and the options, never the triangulation, so any thread may run it.
  WorstCell WorstOfFace(const ScanJob& job) const {
    WorstCell worst{options_.tolerance};
    const auto [row_min, row_max] = CellSpanRows(job.cells, geometry_.height);
    RaiseToWorstInRows(dem_, job.cells, job.plane, row_min, row_max, &worst);
    return Insertable(job, worst);
  }

  // `worst`, the worst cell of the face's spans, is nearly always one the face may insert; when
  // it is not, the slow scan finds the worst of those it may (the same cell the fast one would,
  // when it may).
  WorstCell Insertable(const ScanJob& job, WorstCell worst) const {
    if (worst.col >= 0 &&
        (Skipped(worst.col, worst.row) || !Covers(job.corners, worst.col, worst.row))) {
      worst = InsertableWorstCell(job.corners, job.cells, job.plane);
    }
    return worst;
  }

  // The largest |plane - DEM| above the tolerance over the valid cells of the face's spans, at
  // the first cell that has it (col -1 when none). A face over more than kParallelScanCells
  // cells is scanned in parallel by ranges of rows; joining ranges in row order with the earlier
  // range's cell winning a tie gives the cell one scan finds, however the rows were cut.
  WorstCell AnyWorstCell(const CellTriangle& t, const CellPlane& plane) {
    // Below this, handing part of a scan to another thread costs about what it saves.
    constexpr double kParallelScanCells = 1 << 17;
    const WorstCell floor{options_.tolerance};
    const auto [row_min, row_max] = CellSpanRows(t, geometry_.height);
    const double cells = TriangleCells(t);
    if (!Parallel() || row_max - row_min < 2 || cells < kParallelScanCells) {
      WorstCell worst = floor;
      RaiseToWorstInRows(dem_, t, plane, row_min, row_max, &worst);
      return worst;
    }
    // Rows per range: about kParallelScanCells / 2 cells each.
    const auto rows = static_cast<double>(row_max - row_min + 1);
    const auto grain =
        std::max<size_t>(1, static_cast<size_t>(rows * (kParallelScanCells / 2) / cells));
    return tbb::parallel_reduce(
        tbb::blocked_range<int64_t>(row_min, row_max + 1, grain), floor,
        [&](const tbb::blocked_range<int64_t>& range, WorstCell worst) {
          RaiseToWorstInRows(dem_, t, plane, range.begin(), range.end() - 1, &worst);
          return worst;
        },
        [](const WorstCell& earlier, const WorstCell& later) {
          return later.error > earlier.error ? later : earlier;
        });
  }

  // The face's area in cells: about how many cells its scan reads.
  static double TriangleCells(const CellTriangle& t) {
    return std::fabs((t.col[1] - t.col[0]) * (t.row[2] - t.row[0]) -
                     (t.col[2] - t.col[0]) * (t.row[1] - t.row[0])) /
           2;
  }

  // As AnyWorstCell, counting only cells not skipped and exactly covered; those tests are made
  // on a new maximum only, which is rare.
  WorstCell InsertableWorstCell(const Corners& v, const CellTriangle& t,
                                const CellPlane& plane) const {
    WorstCell worst{options_.tolerance};
    ForEachCellSpan(t, geometry_.width, geometry_.height,
                    [&](int64_t r, int64_t first, int64_t last) {
                      const double y = static_cast<double>(r);
                      dem_.ForEachCell(r, first, last, [&](int64_t c, float value) {
                        if (std::isnan(value)) return;
                        const double error = std::fabs(plane.At(static_cast<double>(c), y) - value);
                        if (error <= worst.error || Skipped(c, r) || !Covers(v, c, r)) return;
                        worst = WorstCell{error, c, r};
                      });
                    });
    return worst;
  }

  // The face in the grid's centre space.
  CellTriangle InCellSpace(const Corners& v) const {
    CellTriangle t;
    for (size_t i = 0; i < 3; ++i) {
      t.col[i] = geometry_.ColumnAt(v[i].x);
      t.row[i] = geometry_.RowAt(v[i].y);
      t.z[i] = v[i].z;
    }
    return t;
  }

  // Only cells the face truly holds (cell_cover.h), so an insertion never lands outside the
  // region.
  bool Covers(const Corners& v, int64_t col, int64_t row) const {
    const auto at = [&](size_t i) { return TinVertex{v[i].x, v[i].y, v[i].z, VertexKind::kDem}; };
    return HoldsCellCentre(geometry_, at(0), at(1), at(2), col, row);
  }

  bool Skipped(int64_t col, int64_t row) const {
    if (!blocked_.empty() && blocked_.count({col, row})) return true;
    return options_.excluded &&
           options_.excluded(geometry_.CellCenterX(col), geometry_.CellCenterY(row));
  }

  Cdt& cdt_;
  CellSource& dem_;
  const GridGeometry& geometry_;
  const RefineOptions& options_;
  std::vector<Queue> queues_;  // one per tile, or one for the whole grid
  int64_t tiles_across_ = 1;
  std::vector<uint32_t> added_;
  std::vector<Cdt::FaceRef> incident_;
  std::vector<ScanJob> jobs_;  // ScanAll's faces, kept to reuse their memory
  std::set<std::pair<int64_t, int64_t>> blocked_;
  bool parallel_ = false;    // options.parallel_scans on a ConcurrentReads DEM
  uint64_t next_stamp_ = 1;  // 0 is a fresh face's stamp, never queued
};

}  // namespace

std::vector<uint32_t> RefineToTolerance(Cdt& cdt, CellSource& dem, const RefineOptions& options,
                                        RefineReport* report) {
  Refiner refiner(cdt, dem, options);
  return refiner.Run(cdt.FiniteFaces(), report);
}

std::vector<uint32_t> RefineFacesToTolerance(Cdt& cdt, CellSource& dem,
                                             const RefineOptions& options,
                                             std::vector<Cdt::FaceRef> faces,
                                             RefineReport* report) {
  Refiner refiner(cdt, dem, options);
  return refiner.Run(std::move(faces), report);
}

std::vector<uint32_t> RefineToTolerance(Cdt& cdt, const Grid& dem, const RefineOptions& options,
                                        RefineReport* report) {
  GridCellSource source(dem);
  return RefineToTolerance(cdt, source, options, report);
}

}  // namespace tinbase
