// locate_bench: bulk point location on a ~1e6-triangle store (issue 24, docs/BENCHMARKS.md,
// "Bulk point location"). tinbase's PointLocator, the walk `tinbase locate --points` streams
// through, against CGAL's in-memory locate() on the same triangulation (the ceiling); PostGIS is
// measured by scripts/bench-locate.sh on the files `postgis-files` writes.
//
//   locate_bench store --dir DIR              builds the store once (bench/store_1e6.h)
//   locate_bench postgis-files --dir DIR --sample N
//                                             triangles.tsv (id, EWKT) and N points of each order
//   locate_bench run --dir DIR --points N --rounds R [--walk-sample W] [--jump-points J]
//                    [--sample M] [--methods a,b]
//
// The points are uniform random over the surface's extent (seeded, the same every run), and the
// same points sorted along a Hilbert curve. Each round times every method on every order in turn
// (alternated, so a machine shared with other work slows all of them alike); the summary gives
// the medians of the rounds and the ratios within each round.
//
// Methods:
//   tinbase        PointLocator::Locate (triangle, z, visible, tag), one read snapshot, each walk
//                  from the last answer
//   tinbase+cache  the same with a MeshCache, so rows read once stay in memory
//   tinbase-bulk   LocatePoints, what `tinbase locate --points` and the service's POST locate
//                  run: the previous answer's triangle tested first, then the walk (a jump when
//                  far); on the in-memory path when the request is large against the surface
//                  (db/query/bulk_locate.h), so its time includes loading the surface
//   tinbase-stored LocatePoints forced onto the stored path (every row read by key)
//   tinbase-memory-walk
//                  the in-memory path's walk alone (MemoryLocator on a MemoryMesh loaded before
//                  the clock starts, as CGAL's triangulations are built before theirs)
//   tinbase-jump   LocatePoint per point (a jump through the centroid blocks, then a walk)
//   cgal-walk      CGAL's locate(p, hint = last face) on a constrained triangulation whose
//                  constraints are every stored edge: exactly the stored triangles
//   cgal-hierarchy CGAL's Delaunay hierarchy of the same vertices, locate(p) with no hint (CGAL's
//                  structure for scattered queries; co-circular grid quads may take the other
//                  diagonal, so its triangles differ from the store's there)
// On random points a walk from the last answer crosses O(sqrt n) triangles, so the walking methods
// run on random points only over the first --walk-sample points; tinbase-jump runs over the first
// --jump-points random points and the first --sample sorted ones (where it only shows what the
// walk from the last answer saves), tinbase-stored over the first --jump-points random points.
// Every other case runs over all --points.
#include <CGAL/Constrained_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_hierarchy_2.h>
#include <CGAL/Triangulation_hierarchy_vertex_base_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <gdal_priv.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "bench/store_1e6.h"
#include "db/mesh_cache.h"
#include "db/point_locator.h"
#include "db/query/bulk_locate.h"
#include "db/query/memory_locator.h"
#include "db/query/memory_mesh.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU time of this process (every method runs on the calling thread alone).
double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

[[noreturn]] void Die(const std::string& what, const Status& status) {
  std::fprintf(stderr, "locate_bench: %s: %s\n", what.c_str(), status.message().c_str());
  std::exit(1);
}

template <typename T>
T Check(Result<T> result, const std::string& what) {
  if (!result.ok()) Die(what, result.status());
  return std::move(*result);
}

struct Pt {
  double x, y;
};

// Position along a Hilbert curve over a 2^16 x 2^16 grid (the classic rotate-and-flip walk).
uint64_t HilbertKey(uint32_t x, uint32_t y) {
  uint64_t d = 0;
  for (uint32_t s = 1u << 15; s > 0; s /= 2) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += static_cast<uint64_t>(s) * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

struct Extent {
  double x0, y0, x1, y1;
};

Extent ExtentOf(const Tin& tin) {
  Extent e{1e300, 1e300, -1e300, -1e300};
  for (const TinVertex& v : tin.vertices) {
    e.x0 = std::min(e.x0, v.x);
    e.y0 = std::min(e.y0, v.y);
    e.x1 = std::max(e.x1, v.x);
    e.y1 = std::max(e.y1, v.y);
  }
  return e;
}

// `n` points uniform over the extent (a millimetre inside it, so every one is on the surface).
std::vector<Pt> RandomPoints(const Extent& e, int64_t n) {
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<double> ux(e.x0 + 1e-3, e.x1 - 1e-3), uy(e.y0 + 1e-3, e.y1 - 1e-3);
  std::vector<Pt> points(static_cast<size_t>(n));
  for (Pt& p : points) p = {ux(rng), uy(rng)};
  return points;
}

std::vector<Pt> HilbertSorted(std::vector<Pt> points, const Extent& e) {
  const double sx = 65535 / (e.x1 - e.x0), sy = 65535 / (e.y1 - e.y0);
  std::vector<std::pair<uint64_t, Pt>> keyed;
  keyed.reserve(points.size());
  for (const Pt& p : points)
    keyed.push_back({HilbertKey(static_cast<uint32_t>((p.x - e.x0) * sx),
                                static_cast<uint32_t>((p.y - e.y0) * sy)),
                     p});
  std::sort(keyed.begin(), keyed.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < keyed.size(); ++i) points[i] = keyed[i].second;
  return points;
}

// --- CGAL -------------------------------------------------------------------------------------

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using CtVb = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, K>;
using CtFb = CGAL::Constrained_triangulation_face_base_2<
    K, CGAL::Triangulation_face_base_with_info_2<int64_t, K>>;
using Ct = CGAL::Constrained_triangulation_2<K, CGAL::Triangulation_data_structure_2<CtVb, CtFb>,
                                             CGAL::No_constraint_intersection_tag>;
using HVb = CGAL::Triangulation_hierarchy_vertex_base_2<CGAL::Triangulation_vertex_base_2<K>>;
using HFb = CGAL::Triangulation_face_base_with_info_2<int64_t, K>;
using Dt = CGAL::Delaunay_triangulation_2<K, CGAL::Triangulation_data_structure_2<HVb, HFb>>;
using Hierarchy = CGAL::Triangulation_hierarchy_2<Dt>;

// The stored triangulation in CGAL: the vertices, then every stored edge as a constraint (an edge
// already present is only marked, a co-circular quad's other diagonal is flipped away), each face
// carrying its store triangle id.
std::unique_ptr<Ct> StoredTriangulation(const LoadedSurface& s) {
  auto ct = std::make_unique<Ct>();
  std::vector<Ct::Vertex_handle> handles(s.tin.vertices.size());
  // In Hilbert order, each insertion located from the last vertex: the walks stay short.
  std::vector<Pt> points;
  for (const TinVertex& v : s.tin.vertices) points.push_back({v.x, v.y});
  const Extent e = ExtentOf(s.tin);
  const double sx = 65535 / (e.x1 - e.x0), sy = 65535 / (e.y1 - e.y0);
  std::vector<std::pair<uint64_t, uint32_t>> order;
  for (uint32_t i = 0; i < points.size(); ++i)
    order.push_back({HilbertKey(static_cast<uint32_t>((points[i].x - e.x0) * sx),
                                static_cast<uint32_t>((points[i].y - e.y0) * sy)),
                     i});
  std::sort(order.begin(), order.end());
  Ct::Face_handle near;
  for (const auto& [key, i] : order) {
    const Ct::Vertex_handle v = ct->insert({points[i].x, points[i].y}, near);
    v->info() = i;
    handles[i] = v;
    near = v->face();
  }
  for (const TinTriangle& t : s.tin.triangles)
    for (int i = 0; i < 3; ++i)
      if (t.v[i] < t.v[(i + 1) % 3] || t.n[(i + 2) % 3] == kNoNeighbour)
        ct->insert_constraint(handles[t.v[i]], handles[t.v[(i + 1) % 3]]);
  for (auto f = ct->all_faces_begin(); f != ct->all_faces_end(); ++f) f->info() = -1;
  Ct::Face_handle hint;
  for (size_t k = 0; k < s.tin.triangles.size(); ++k) {
    const TinTriangle& t = s.tin.triangles[k];
    double cx = 0, cy = 0;
    for (uint32_t v : t.v) cx += s.tin.vertices[v].x / 3, cy += s.tin.vertices[v].y / 3;
    hint = ct->locate({cx, cy}, hint);
    hint->info() = s.triangle_ids[k];
  }
  return ct;
}

// --- Runs -------------------------------------------------------------------------------------

struct Run {
  double seconds = 0;
  int64_t points = 0;
  double mean_steps = 0;  // triangles visited per point, where the method reports it
  int64_t checksum = 0;   // sum of the triangle ids found
};

using Method = std::function<Run(const std::vector<Pt>&, int64_t count)>;

struct Bench {
  std::unique_ptr<Store> store;
  SurfaceInfo surface;
  std::unique_ptr<Ct> ct;
  std::unique_ptr<Hierarchy> hierarchy;
  std::optional<MemoryMesh> mesh;  // for tinbase-memory-walk
};

// What `tinbase locate --points` runs (db/query/bulk_locate.h): the last triangle tested in
// memory first, then the walk from it.
Run TinbaseBulkRun(Bench& b, const std::vector<Pt>& pts, int64_t count, LocatePath path) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Point2> points;
  points.reserve(static_cast<size_t>(count));
  for (int64_t i = 0; i < count; ++i)
    points.push_back({pts[static_cast<size_t>(i)].x, pts[static_cast<size_t>(i)].y});
  Run run;
  int64_t steps = 0;
  const Status located = LocatePointsBy(path, *b.store, b.surface, points,
                                        [&](size_t, const Point2&, const Location* at) {
                                          if (at == nullptr)
                                            return Status::NotFound("a point is outside");
                                          run.checksum += at->triangle;
                                          steps += at->steps;
                                          return Status::Ok();
                                        });
  if (!located.ok()) Die("locate", located);
  run.seconds = Seconds(start);
  run.points = count;
  run.mean_steps = static_cast<double>(steps) / static_cast<double>(count);
  return run;
}

// The in-memory walk alone, on the mesh loaded once before the runs.
Run MemoryWalkRun(Bench& b, const std::vector<Pt>& pts, int64_t count) {
  const auto start = std::chrono::steady_clock::now();
  MemoryLocator locator(*b.mesh, b.surface);
  Run run;
  int64_t steps = 0;
  for (int64_t i = 0; i < count; ++i) {
    const Pt& p = pts[static_cast<size_t>(i)];
    const Location* at = Check(locator.Locate({p.x, p.y}), "locate");
    if (at == nullptr) Die("locate", Status::NotFound("a point is outside"));
    run.checksum += at->triangle;
    steps += at->steps;
  }
  run.seconds = Seconds(start);
  run.points = count;
  run.mean_steps = static_cast<double>(steps) / static_cast<double>(count);
  return run;
}

Run TinbaseRun(Bench& b, const std::vector<Pt>& pts, int64_t count, bool cached) {
  const auto start = std::chrono::steady_clock::now();
  auto snapshot = Check(ReadSnapshot::Begin(*b.store), "read snapshot");
  std::unique_ptr<MeshCache> cache;
  if (cached) cache = std::make_unique<MeshCache>(*b.store, b.surface);
  PointLocator locator(*b.store, b.surface, cache.get());
  Run run;
  int64_t steps = 0;
  for (int64_t i = 0; i < count; ++i) {
    const Pt& p = pts[static_cast<size_t>(i)];
    const Location at = Check(locator.Locate(p.x, p.y), "locate");
    run.checksum += at.triangle;
    steps += at.steps;
  }
  run.seconds = Seconds(start);
  run.points = count;
  run.mean_steps = static_cast<double>(steps) / static_cast<double>(count);
  return run;
}

Run TinbaseJumpRun(Bench& b, const std::vector<Pt>& pts, int64_t count) {
  const auto start = std::chrono::steady_clock::now();
  auto snapshot = Check(ReadSnapshot::Begin(*b.store), "read snapshot");
  Run run;
  int64_t steps = 0;
  for (int64_t i = 0; i < count; ++i) {
    const Pt& p = pts[static_cast<size_t>(i)];
    const Location at = Check(LocatePoint(*b.store, b.surface, p.x, p.y), "locate");
    run.checksum += at.triangle;
    steps += at.steps;
  }
  run.seconds = Seconds(start);
  run.points = count;
  run.mean_steps = static_cast<double>(steps) / static_cast<double>(count);
  return run;
}

Run CgalWalkRun(const Ct& ct, const std::vector<Pt>& pts, int64_t count) {
  const auto start = std::chrono::steady_clock::now();
  Run run;
  Ct::Face_handle hint;
  for (int64_t i = 0; i < count; ++i) {
    const Pt& p = pts[static_cast<size_t>(i)];
    hint = ct.locate({p.x, p.y}, hint);
    run.checksum += hint->info();
  }
  run.seconds = Seconds(start);
  run.points = count;
  return run;
}

Run CgalHierarchyRun(const Hierarchy& h, const std::vector<Pt>& pts, int64_t count) {
  const auto start = std::chrono::steady_clock::now();
  Run run;
  for (int64_t i = 0; i < count; ++i) {
    const Pt& p = pts[static_cast<size_t>(i)];
    run.checksum += h.locate({p.x, p.y})->info();
  }
  run.seconds = Seconds(start);
  run.points = count;
  return run;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

struct RunArgs {
  std::string dir;
  int64_t points = 10000000;
  int64_t sample = 100000;
  int64_t walk_sample = 2000;
  int64_t jump_points = 1000000;
  int rounds = 2;
  std::string methods =
      "tinbase-bulk,tinbase-memory-walk,tinbase-stored,tinbase,tinbase-jump,cgal-walk,"
      "cgal-hierarchy";
};

// A hierarchy face's store id: the stored triangle holding its centroid (the same triangle
// wherever the two triangulations agree).
void LabelHierarchy(Hierarchy& h, const Ct& ct) {
  Ct::Face_handle hint;
  for (auto f = h.finite_faces_begin(); f != h.finite_faces_end(); ++f) {
    const K::Point_2 c =
        CGAL::centroid(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point());
    hint = ct.locate(c, hint);
    f->info() = hint->info();
  }
}

int RunAll(const RunArgs& args) {
  Bench b;
  b.store = Check(Store::Open(Store1e6(args.dir), Store::Access::kReadOnly), "open store");
  SurfaceStore surfaces(*b.store);
  b.surface = Check(surfaces.Find(kStore1e6Surface), "surface");
  const LoadedSurface loaded = Check(surfaces.Load(b.surface), "load");
  const Extent extent = ExtentOf(loaded.tin);
  std::printf("store: %zu triangles, %zu vertices\n", loaded.tin.triangles.size(),
              loaded.tin.vertices.size());

  auto t0 = std::chrono::steady_clock::now();
  const std::vector<Pt> random = RandomPoints(extent, args.points);
  const std::vector<Pt> sorted = HilbertSorted(random, extent);
  std::printf("points: %" PRId64 " (%.1f s to make and sort)\n", args.points, Seconds(t0));
  const bool want_cgal = args.methods.find("cgal") != std::string::npos;
  if (want_cgal) {
    t0 = std::chrono::steady_clock::now();
    b.ct = StoredTriangulation(loaded);
    std::printf("CGAL constrained triangulation of the stored edges: %zu faces (%.1f s)\n",
                b.ct->number_of_faces(), Seconds(t0));
    t0 = std::chrono::steady_clock::now();
    b.hierarchy = std::make_unique<Hierarchy>();
    std::vector<K::Point_2> points;
    for (const TinVertex& v : loaded.tin.vertices) points.push_back({v.x, v.y});
    b.hierarchy->insert(points.begin(), points.end());
    LabelHierarchy(*b.hierarchy, *b.ct);
    std::printf("CGAL Delaunay hierarchy: %zu faces (%.1f s)\n", b.hierarchy->number_of_faces(),
                Seconds(t0));
  }

  if (args.methods.find("tinbase-memory-walk") != std::string::npos) {
    t0 = std::chrono::steady_clock::now();
    const double cpu0 = CpuSeconds();
    auto snapshot = Check(ReadSnapshot::Begin(*b.store), "read snapshot");
    b.mesh = Check(MemoryMesh::Load(*b.store, b.surface), "load the mesh");
    if (!b.mesh) Die("load the mesh", Status::Corruption("rows not held by position"));
    std::printf("MemoryMesh::Load: %zu triangles (%.2f s, %.2f s CPU)\n", b.mesh->TriangleCount(),
                Seconds(t0), CpuSeconds() - cpu0);
  }

  std::map<std::string, Method> all = {
      {"tinbase", [&](const auto& p, int64_t n) { return TinbaseRun(b, p, n, false); }},
      {"tinbase+cache", [&](const auto& p, int64_t n) { return TinbaseRun(b, p, n, true); }},
      {"tinbase-jump", [&](const auto& p, int64_t n) { return TinbaseJumpRun(b, p, n); }},
      {"tinbase-bulk",
       [&](const auto& p, int64_t n) { return TinbaseBulkRun(b, p, n, LocatePath::kChoose); }},
      {"tinbase-stored",
       [&](const auto& p, int64_t n) { return TinbaseBulkRun(b, p, n, LocatePath::kStored); }},
      {"tinbase-memory-walk", [&](const auto& p, int64_t n) { return MemoryWalkRun(b, p, n); }},
      {"cgal-walk", [&](const auto& p, int64_t n) { return CgalWalkRun(*b.ct, p, n); }},
      {"cgal-hierarchy",
       [&](const auto& p, int64_t n) { return CgalHierarchyRun(*b.hierarchy, p, n); }},
  };
  std::vector<std::string> methods;
  for (size_t at = 0; at <= args.methods.size();) {
    const size_t comma = std::min(args.methods.find(',', at), args.methods.size());
    const std::string name = args.methods.substr(at, comma - at);
    if (!all.count(name)) {
      std::fprintf(stderr, "locate_bench: unknown method '%s'\n", name.c_str());
      return 1;
    }
    methods.push_back(name);
    at = comma + 1;
  }

  const auto count_for = [&](const std::string& method, bool is_random) {
    const bool walks = method == "tinbase" || method == "tinbase+cache" || method == "cgal-walk";
    int64_t n = args.points;
    if (is_random && walks) n = args.walk_sample;
    if (method == "tinbase-jump") n = is_random ? args.jump_points : args.sample;
    if (method == "tinbase-stored" && is_random) n = args.jump_points;
    return std::min(n, args.points);
  };
  // key "method/order" -> CPU ns per point, one per round. CPU time, because on a machine shared
  // with other work the wall time measures the scheduler as much as the method.
  std::map<std::string, std::vector<double>> ns;
  std::map<std::string, std::vector<double>> steps;
  std::map<std::string, int64_t> checksums;
  std::printf(
      "round,method,order,points,seconds,cpu_seconds,ns_per_point,wall_ns_per_point,mean_steps,"
      "checksum\n");
  for (int round = 1; round <= args.rounds; ++round) {
    for (const char* order : {"sorted", "random"}) {
      const bool is_random = std::string(order) == "random";
      const std::vector<Pt>& pts = is_random ? random : sorted;
      // Rotate the method order from round to round so no method always runs first.
      for (size_t k = 0; k < methods.size(); ++k) {
        const std::string& m = methods[(k + static_cast<size_t>(round) - 1) % methods.size()];
        const double cpu0 = CpuSeconds();
        const Run r = all[m](pts, count_for(m, is_random));
        const double cpu = CpuSeconds() - cpu0;
        const double per = cpu * 1e9 / static_cast<double>(r.points);
        std::printf("%d,%s,%s,%" PRId64 ",%.3f,%.3f,%.1f,%.1f,%.2f,%" PRId64 "\n", round, m.c_str(),
                    order, r.points, r.seconds, cpu, per,
                    r.seconds * 1e9 / static_cast<double>(r.points), r.mean_steps, r.checksum);
        std::fflush(stdout);
        const std::string key = m + "/" + order;
        ns[key].push_back(per);
        steps[key].push_back(r.mean_steps);
        checksums[key + "/" + std::to_string(r.points)] = r.checksum;
      }
    }
  }
  std::printf(
      "\nsummary (median of %d rounds): method/order, points, CPU ns per point, "
      "points per second, mean steps, x cgal-walk, x cgal-hierarchy\n",
      args.rounds);
  for (const auto& [key, values] : ns) {
    const std::string order = key.substr(key.find('/') + 1);
    const double per = Median(values);
    const auto ratio = [&](const std::string& peer) {
      auto it = ns.find(peer + "/" + order);
      return it == ns.end() ? 0.0 : per / Median(it->second);
    };
    const std::string method = key.substr(0, key.find('/'));
    std::printf("%s,%" PRId64 ",%.1f,%.0f,%.2f,%.2f,%.2f\n", key.c_str(),
                count_for(method, order == "random"), per, 1e9 / per, Median(steps[key]),
                ratio("cgal-walk"), ratio("cgal-hierarchy"));
  }
  std::printf("\nchecksums (sum of triangle ids; equal sums for equal point counts agree):\n");
  for (const auto& [key, sum] : checksums) std::printf("%s,%" PRId64 "\n", key.c_str(), sum);
  return 0;
}

// triangles.tsv: "id<TAB>SRID=32632;POLYGON((...))" for COPY; points_{random,sorted}.tsv:
// "i<TAB>x<TAB>y", the first `sample` random points and the same points in Hilbert order.
int PostgisFiles(const std::string& dir, int64_t sample) {
  auto store = Check(Store::Open(Store1e6(dir), Store::Access::kReadOnly), "open store");
  SurfaceStore surfaces(*store);
  const LoadedSurface loaded =
      Check(surfaces.Load(Check(surfaces.Find(kStore1e6Surface), "surface")), "load");
  {
    std::ofstream out(dir + "/triangles.tsv");
    char line[512];
    for (size_t k = 0; k < loaded.tin.triangles.size(); ++k) {
      const TinTriangle& t = loaded.tin.triangles[k];
      const TinVertex& a = loaded.tin.vertices[t.v[0]];
      const TinVertex& b = loaded.tin.vertices[t.v[1]];
      const TinVertex& c = loaded.tin.vertices[t.v[2]];
      std::snprintf(line, sizeof line,
                    "%" PRId64
                    "\tSRID=32632;POLYGON((%.17g %.17g,%.17g %.17g,%.17g %.17g,%.17g "
                    "%.17g))\n",
                    loaded.triangle_ids[k], a.x, a.y, b.x, b.y, c.x, c.y, a.x, a.y);
      out << line;
    }
  }
  const Extent extent = ExtentOf(loaded.tin);
  const std::vector<Pt> random = RandomPoints(extent, sample);
  const std::vector<Pt> sorted = HilbertSorted(random, extent);
  for (const auto& [name, pts] : {std::pair{"random", &random}, std::pair{"sorted", &sorted}}) {
    std::ofstream out(dir + "/points_" + name + ".tsv");
    char line[128];
    for (size_t i = 0; i < pts->size(); ++i) {
      std::snprintf(line, sizeof line, "%zu\t%.17g\t%.17g\n", i, (*pts)[i].x, (*pts)[i].y);
      out << line;
    }
  }
  std::printf("wrote %s/triangles.tsv (%zu) and points_{random,sorted}.tsv (%" PRId64 ")\n",
              dir.c_str(), loaded.tin.triangles.size(), sample);
  return 0;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  CLI::App app{"locate_bench: bulk point location, tinbase against CGAL (PostGIS: the script)"};
  app.require_subcommand(1);
  std::string dir;
  CLI::App* store = app.add_subcommand("store", "Build the ~1e6-triangle store once");
  store->add_option("--dir", dir)->required();
  int64_t sample = 100000;
  CLI::App* files = app.add_subcommand("postgis-files", "Triangles and sample points for PostGIS");
  files->add_option("--dir", dir)->required();
  files->add_option("--sample", sample);
  tinbase::RunArgs args;
  CLI::App* run = app.add_subcommand("run", "Time every method on sorted and random points");
  run->add_option("--dir", args.dir)->required();
  run->add_option("--points", args.points);
  run->add_option("--walk-sample", args.walk_sample, "Random points for the walks from the last");
  run->add_option("--jump-points", args.jump_points, "Random points for tinbase-jump");
  run->add_option("--sample", args.sample, "Sorted points for tinbase-jump");
  run->add_option("--rounds", args.rounds);
  run->add_option("--methods", args.methods);
  CLI11_PARSE(app, argc, argv);
  GDALAllRegister();
  if (*store) {
    tinbase::Store1e6(dir);
    return 0;
  }
  if (*files) return tinbase::PostgisFiles(dir, sample);
  return tinbase::RunAll(args);
}
