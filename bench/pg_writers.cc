// Inserts per second on one PostgreSQL surface with 1, 2 and 4 concurrent writers in disjoint
// regions (docs/scaling.md, "Writers"; docs/BENCHMARKS.md, "Concurrent writers on PostgreSQL").
//
// The store: the Hamersley DEM and a surface built from it at 10 m (as `tinbase init`, `dem
// import` and `tin build --tolerance 10` make it). Writer w of n inserts small random polygons
// (fill, one transaction each, through AddPolygons on a Store of its own, as `tinbase polygon add`
// does) in stripe w of n vertical stripes of the map, so no two writers' regions meet. Each round
// runs every writer count in turn, in an order that alternates between rounds; a case stops after
// `seconds` of wall time, and the rate is its committed inserts over its wall time.
//
// Usage: pg_writers POSTGRES_URL [rounds=3] [seconds=30] [csv]
// The URL is a server's (scripts/pg-server.sh start DIR prints one); a fresh schema is used.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "db/dem_store.h"
#include "db/polygon_editor.h"
#include "db/store.h"
#include "db/surface_builder.h"

namespace {

constexpr double kCx = 539298, kCy = 7497339;  // the middle of the Hamersley DEM (EPSG:28350)
constexpr double kHalfWidth = 16000;           // the stripes span x in kCx +- this

// The store: the Hamersley DEM and a surface built from it at 10 m, as `tinbase init`, `dem
// import` and `tin build --tolerance 10` make it.
tinbase::Status BuildStore(const std::string& store) {
  TB_ASSIGN_OR_RETURN(auto created, tinbase::Store::Create(store, ""));
  tinbase::DemStore dems(*created);
  TB_RETURN_IF_ERROR(
      dems.Import({std::string(TINBASE_DATA_DIR) + "/geology/hamersley/dtm_rp.tif"}, {}).status());
  tinbase::SurfaceBuildOptions options;
  options.surface = "terrain";
  options.greedy.tolerance = 10;
  return tinbase::BuildSurfaceFromDem(*created, options).status();
}

// A convex 6-gon of radius 150 to 300 m at a random point of stripe `w` of `n`, as GeoJSON.
std::string Polygon(std::mt19937_64& random, int w, int n) {
  const double width = 2 * kHalfWidth / n;
  const double left = kCx - kHalfWidth + w * width;
  std::uniform_real_distribution<double> x(left + 400, left + width - 400),
      y(kCy - 12000, kCy + 12000), r(150, 300);
  const double cx = x(random), cy = y(random), radius = r(random);
  std::ostringstream out;
  out.precision(17);
  out << R"({"type":"FeatureCollection","crs":{"type":"name","properties":{"name":"EPSG:28350"}},)"
      << R"("features":[{"type":"Feature","properties":{},"geometry":{"type":"Polygon",)"
      << R"("coordinates":[[)";
  for (int k = 0; k <= 6; ++k) {
    const double a = 2 * M_PI * (k % 6) / 6;
    out << (k == 0 ? "" : ",") << "[" << cx + radius * std::cos(a) << ","
        << cy + radius * std::sin(a) << "]";
  }
  out << "]]}}]}";
  return out.str();
}

struct Outcome {
  int64_t inserts = 0;
  int64_t failures = 0;
  double seconds = 0;
};

// `writers` threads insert polygons in their stripes for `seconds`.
Outcome RunCase(const std::string& store, int writers, double seconds, const std::string& dir,
                int round) {
  std::atomic<int64_t> inserts{0}, failures{0};
  const auto start = std::chrono::steady_clock::now();
  const auto until = start + std::chrono::duration<double>(seconds);
  std::vector<std::thread> threads;
  for (int w = 0; w < writers; ++w)
    threads.emplace_back([&, w] {
      auto opened = tinbase::Store::Open(store, tinbase::Store::Access::kReadWrite);
      if (!opened.ok()) {
        std::fprintf(stderr, "%s\n", opened.status().ToString().c_str());
        ++failures;
        return;
      }
      std::mt19937_64 random(round * 100 + writers * 10 + w);
      const std::string file = dir + "/r" + std::to_string(round) + "n" + std::to_string(writers) +
                               "w" + std::to_string(w) + ".geojson";
      while (std::chrono::steady_clock::now() < until) {
        std::ofstream(file) << Polygon(random, w, writers);
        tinbase::PolygonAddOptions options;
        options.surface = "terrain";
        options.file = file;
        options.mode = tinbase::FeatureMode::kFill;
        auto report = tinbase::AddPolygons(**opened, options);
        if (report.ok()) {
          ++inserts;
        } else {
          ++failures;
          std::fprintf(stderr, "writer %d: %s\n", w, report.status().ToString().c_str());
        }
      }
    });
  for (std::thread& t : threads) t.join();
  Outcome out;
  out.inserts = inserts;
  out.failures = failures;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s POSTGRES_URL [rounds] [seconds] [csv]\n", argv[0]);
    return 2;
  }
  const std::string url = argv[1];
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
  const double seconds = argc > 3 ? std::atof(argv[3]) : 30;
  const std::string csv = argc > 4 ? argv[4] : "";
  const std::string store = url + "?schema=bench_writers_" + std::to_string(getpid());
  char dir_template[] = "/tmp/pg_writers_XXXXXX";
  const std::string dir = mkdtemp(dir_template);
  if (tinbase::Status built = BuildStore(store); !built.ok()) {
    std::fprintf(stderr, "%s\n", built.ToString().c_str());
    return 1;
  }
  std::FILE* out = csv.empty() ? nullptr : std::fopen(csv.c_str(), "w");
  if (out != nullptr) std::fprintf(out, "round,writers,inserts,failures,seconds,inserts_per_s\n");
  std::printf("round writers inserts failures seconds inserts/s\n");
  for (int round = 0; round < rounds; ++round) {
    std::vector<int> order = {1, 2, 4};
    if (round % 2 == 1) order = {4, 2, 1};
    for (int writers : order) {
      const Outcome o = RunCase(store, writers, seconds, dir, round);
      const double rate = static_cast<double>(o.inserts) / o.seconds;
      std::printf("%d %d %lld %lld %.1f %.2f\n", round, writers, static_cast<long long>(o.inserts),
                  static_cast<long long>(o.failures), o.seconds, rate);
      std::fflush(stdout);
      if (out != nullptr)
        std::fprintf(out, "%d,%d,%lld,%lld,%.2f,%.3f\n", round, writers,
                     static_cast<long long>(o.inserts), static_cast<long long>(o.failures),
                     o.seconds, rate);
    }
  }
  if (out != nullptr) std::fclose(out);
  return 0;
}
