// pg_speed_bench: the same workloads on SQLite and PostgreSQL, in one run (issue 27's speed table,
// docs/BENCHMARKS.md "PostgreSQL"):
//   - bulk TIN write: the ~1e6-triangle surface of bench/store_1e6.h's terrain (loaded once into
//     memory) written as a new surface into a fresh store and committed (vertices, triangles and
//     constraints through db/sql/bulk_write.h: multi-row INSERTs on SQLite, COPY on PostgreSQL);
//   - point location: random points over the surface, on the stored path (every row read by key,
//     what a small request runs) and through LocatePoints as `tinbase locate --points` runs it
//     for a large request (the surface loaded, then walked in memory);
//   - single-polygon insert latency: a 200-vertex fill at the centre (db/polygon_editor.h
//     AddPolygons, one transaction), each undone untimed, as update_bench's BM_Insert200.
//
//   pg_speed_bench --dir DIR --postgres URL [--rounds R] [--stored-points N] [--bulk-points M]
//                  [--inserts K]
//
// Every round runs each workload on SQLite, then on PostgreSQL (alternated, so a machine shared
// with other work slows both alike); the summary gives each backend's median over the rounds and
// the ratio PostgreSQL / SQLite of each round's pair. URL is a server of scripts/pg-server.sh (its
// durability settings are the caller's: scripts/bench-pg.sh turns fsync back on); the bench
// makes schemas pgspeed_* there and drops its bulk-write schemas again.
#include <gdal_priv.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench/generated_terrain.h"
#include "core/geometry/crs.h"
#include "core/raster/gdal_raster.h"
#include "db/dem_store.h"
#include "db/polygon_editor.h"
#include "db/query/bulk_locate.h"
#include "db/sql/connection.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"

namespace tinbase {
namespace {

constexpr int64_t kSide = 709;  // cells of the terrain: ~1e6 triangles at full resolution
constexpr const char* kSurface = "terrain";

[[noreturn]] void Die(const std::string& what, const Status& s) {
  std::fprintf(stderr, "pg_speed_bench: %s: %s\n", what.c_str(), s.ToString().c_str());
  std::exit(1);
}

template <typename T>
T Check(Result<T> r, const std::string& what) {
  if (!r.ok()) Die(what, r.status());
  return std::move(*r);
}

void Check(const Status& s, const std::string& what) {
  if (!s.ok()) Die(what, s);
}

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0 : (n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2);
}

// The two backends' store targets: a file in DIR, or a schema of the server.
struct Backend {
  std::string name;
  std::string base;  // DIR/ or URL?schema=
  bool postgres = false;
  std::string Target(const std::string& label) const {
    return postgres ? base + "pgspeed_" + label : base + "pgspeed_" + label + ".tinbase";
  }
};

// Removes the store `label` of `b`: its files, or its schema.
void Drop(const Backend& b, const std::string& label, const std::string& url) {
  if (!b.postgres) {
    for (const char* suffix : {"", "-wal", "-shm"})
      std::filesystem::remove(b.Target(label) + suffix);
    return;
  }
  auto admin = Check(Connection::Open(url + "?schema=public", Connection::Mode::kReadWrite),
                     "connecting to " + url);
  Check(admin->Exec("DROP SCHEMA IF EXISTS pgspeed_" + label + " CASCADE"), "dropping a schema");
}

// The store of `b` with the terrain's DEM and its surface built at full resolution (untimed).
std::unique_ptr<Store> SetUpStore(const Backend& b, const std::string& tif,
                                  const std::string& url) {
  const std::string target = b.Target("setup");
  if (auto open = Store::Open(target); open.ok()) {
    if (SurfaceStore(**open).Find(kSurface).ok()) return std::move(*open);
  }
  Drop(b, "setup", url);
  auto store = Check(Store::Create(target, ""), "creating " + target);
  Check(DemStore(*store).Import({tif}, {}).status(), "importing the DEM into " + target);
  SurfaceBuildOptions o;
  o.surface = kSurface;
  o.greedy.tolerance = 1e-3;
  const auto built = Check(BuildSurfaceFromDem(*store, o), "building the surface of " + target);
  std::printf("%s: built %lld triangles\n", b.name.c_str(),
              static_cast<long long>(built.triangles));
  return store;
}

// Seconds to write `tin` as a new surface into a fresh store of `b`, committed.
double BulkWrite(const Backend& b, const LoadedSurface& loaded, const SurfaceInfo& info,
                 const std::string& url) {
  Drop(b, "bulk", url);
  auto store = Check(Store::Create(b.Target("bulk"), "EPSG:32632"), "creating the bulk store");
  const auto start = std::chrono::steady_clock::now();
  auto tx = Check(store->BeginWrite(), "begin");
  SurfaceInfo spec;
  spec.name = kSurface;
  spec.method = "copy";
  spec.blocks = info.blocks;
  Check(SurfaceStore(*store).Create(spec, loaded.tin).status(), "writing the surface");
  Check(tx->Commit(), "commit");
  const double seconds = Seconds(start);
  store.reset();
  Drop(b, "bulk", url);
  return seconds;
}

// Points per second located by LocatePointsBy(`path`) over `points`; *inside gets how many were
// on the surface, printed per backend so a run shows both answered alike.
double Locate(Store& store, const std::vector<Point2>& points, LocatePath path, int64_t* inside) {
  const SurfaceInfo surface = Check(SurfaceStore(store).Find(kSurface), "surface");
  *inside = 0;
  const auto start = std::chrono::steady_clock::now();
  Check(LocatePointsBy(path, store, surface, points,
                       [&](size_t, const Point2&, const Location* at) {
                         if (at != nullptr) ++*inside;
                         return Status::Ok();
                       }),
        "locate");
  return static_cast<double>(points.size()) / Seconds(start);
}

// The 200-vertex polygon of update_bench's BM_Insert200 scaled to this terrain: radius 30 cells
// around the centre, as GeoJSON in EPSG:32632.
std::string PolygonFile(const std::string& dir, double cx, double cy) {
  const std::string path = dir + "/pg_speed_ngon.geojson";
  std::ofstream out(path);
  out.precision(17);
  out << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
      << R"("urn:ogc:def:crs:EPSG::32632"}}, "features": [{"type": "Feature", "properties": )"
      << R"({"unit": "granite"}, "geometry": {"type": "Polygon", "coordinates": [[)";
  constexpr int kVertices = 200;
  for (int k = 0; k <= kVertices; ++k) {
    const double a = 2 * M_PI * (k % kVertices) / kVertices + 0.05;
    out << (k ? "," : "") << "[" << cx + 30 * std::cos(a) << "," << cy + 30 * std::sin(a) << "]";
  }
  out << "]]}}]}\n";
  return path;
}

// Milliseconds of `inserts` inserts of the polygon (each undone, untimed), their median.
double InsertMs(Store& store, const std::string& polygon, int inserts) {
  PolygonAddOptions o;
  o.surface = kSurface;
  o.file = polygon;
  o.mode = FeatureMode::kFill;
  o.tag_field = "unit";
  std::vector<double> ms;
  for (int i = 0; i < inserts; ++i) {
    const auto start = std::chrono::steady_clock::now();
    const auto report = Check(AddPolygons(store, o), "polygon add");
    ms.push_back(Seconds(start) * 1000);
    Check(RemovePolygon(store, report.first_feature_id).status(), "polygon remove");
  }
  return Median(ms);
}

struct Sample {
  double bulk_s = 0, stored_pps = 0, bulk_pps = 0, insert_ms = 0;
};

int Run(const std::string& dir, const std::string& url, int rounds, int64_t stored_points,
        int64_t bulk_points, int inserts) {
  GDALAllRegister();
  std::filesystem::create_directories(dir);
  Grid grid = GeneratedTerrain(kSide);
  grid.crs_wkt = Check(Crs::FromUserInput("EPSG:32632"), "crs").Wkt();
  const std::string tif = dir + "/pg_speed_dem.tif";
  Check(WriteGeoTiff(grid, tif), "writing " + tif);

  const std::vector<Backend> backends = {{"sqlite", dir + "/", false},
                                         {"postgresql", url + "?schema=", true}};
  std::vector<std::unique_ptr<Store>> stores;
  for (const Backend& b : backends) stores.push_back(SetUpStore(b, tif, url));
  SurfaceStore sqlite_surfaces(*stores[0]);
  const SurfaceInfo info = Check(sqlite_surfaces.Find(kSurface), "surface");
  const LoadedSurface loaded = Check(sqlite_surfaces.Load(info), "loading the surface");
  std::printf("surface: %zu vertices, %zu triangles, %zu constraints\n", loaded.tin.vertices.size(),
              loaded.tin.triangles.size(), loaded.tin.constraints.size());

  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const TinVertex& v : loaded.tin.vertices) {
    min_x = std::min(min_x, v.x), max_x = std::max(max_x, v.x);
    min_y = std::min(min_y, v.y), max_y = std::max(max_y, v.y);
  }
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> ux(min_x, max_x), uy(min_y, max_y);
  std::vector<Point2> points(static_cast<size_t>(std::max(stored_points, bulk_points)));
  for (Point2& p : points) p = {ux(rng), uy(rng)};
  const std::vector<Point2> stored(points.begin(), points.begin() + stored_points);
  const std::vector<Point2> bulk(points.begin(), points.begin() + bulk_points);
  const std::string polygon =
      PolygonFile(dir, (min_x + max_x) / 2 + 0.37, (min_y + max_y) / 2 + 0.21);

  std::map<std::string, std::vector<Sample>> samples;
  for (int round = 0; round < rounds; ++round) {
    for (size_t i = 0; i < backends.size(); ++i) {
      const Backend& b = backends[i];
      Sample s;
      s.bulk_s = BulkWrite(b, loaded, info, url);
      int64_t inside_stored = 0, inside_bulk = 0;
      s.stored_pps = Locate(*stores[i], stored, LocatePath::kStored, &inside_stored);
      s.bulk_pps = Locate(*stores[i], bulk, LocatePath::kChoose, &inside_bulk);
      s.insert_ms = InsertMs(*stores[i], polygon, inserts);
      std::printf(
          "round %d %-10s bulk write %.2f s | stored locate %.0f pts/s (%lld inside) | bulk "
          "locate %.0f pts/s (%lld inside) | insert %.1f ms\n",
          round + 1, b.name.c_str(), s.bulk_s, s.stored_pps, static_cast<long long>(inside_stored),
          s.bulk_pps, static_cast<long long>(inside_bulk), s.insert_ms);
      std::fflush(stdout);
      samples[b.name].push_back(s);
    }
  }

  const auto column = [&](const std::string& name, double Sample::*field) {
    std::vector<double> v;
    for (const Sample& s : samples[name]) v.push_back(s.*field);
    return v;
  };
  const auto ratios = [&](double Sample::*field) {
    std::vector<double> v;
    for (size_t r = 0; r < samples["sqlite"].size(); ++r)
      v.push_back(samples["postgresql"][r].*field / samples["sqlite"][r].*field);
    return v;
  };
  struct Row {
    const char* what;
    const char* unit;
    double Sample::*field;
  };
  const Row rows[] = {
      {"bulk TIN write (1e6 triangles)", "s", &Sample::bulk_s},
      {"point location, stored path", "points/s", &Sample::stored_pps},
      {"point location, LocatePoints", "points/s", &Sample::bulk_pps},
      {"200-vertex polygon insert", "ms", &Sample::insert_ms},
  };
  std::printf(
      "\n| workload | unit | SQLite | PostgreSQL | PostgreSQL / SQLite (median, min-max) |\n");
  std::printf("|---|---|---:|---:|---|\n");
  for (const Row& row : rows) {
    std::vector<double> r = ratios(row.field);
    std::sort(r.begin(), r.end());
    std::printf("| %s | %s | %.4g | %.4g | %.2f (%.2f-%.2f) |\n", row.what, row.unit,
                Median(column("sqlite", row.field)), Median(column("postgresql", row.field)),
                Median(r), r.front(), r.back());
  }
  return 0;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  CLI::App app{"SQLite against PostgreSQL on the same workloads"};
  std::string dir, url;
  int rounds = 3, inserts = 10;
  int64_t stored_points = 20000, bulk_points = 1000000;
  app.add_option("--dir", dir, "where the SQLite stores and the DEM go")->required();
  app.add_option("--postgres", url, "the server's URL (scripts/pg-server.sh)")->required();
  app.add_option("--rounds", rounds);
  app.add_option("--stored-points", stored_points);
  app.add_option("--bulk-points", bulk_points);
  app.add_option("--inserts", inserts);
  CLI11_PARSE(app, argc, argv);
  return tinbase::Run(dir, url, rounds, stored_points, bulk_points, inserts);
}
