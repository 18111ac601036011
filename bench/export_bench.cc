// export_bench: `tinbase export` of the ~1e6-triangle store (bench/store_1e6.h) to each format
// (issue 24, docs/BENCHMARKS.md, "Export"): wall time, bytes per triangle and peak memory of the
// whole command (open, load, write), each run in a child process so its peak RSS is its own.
// Each round exports every format once, in an order rotated from round to round, so a machine
// shared with other work slows every format alike; the summary gives the medians of the rounds
// and each format's time over OBJ's within a round. A format the CLI does not know (yet) is
// reported as such with the CLI's message, so the table fills in as formats land.
//
//   export_bench --dir DIR [--formats obj,geojson,ply,stl,glb,gpkg,landxml] [--rounds 3]
//                [--cli PATH/TO/tinbase]
#include <gdal_priv.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench/store_1e6.h"

namespace tinbase {
namespace {

struct Export {
  bool ok = false;
  double seconds = 0;
  double cpu_seconds = 0;  // user + system of the child
  int64_t peak_rss_kib = 0;
  int64_t bytes = 0;
  std::string error;  // the CLI's stderr when it failed
};

// The file name extension of each format (the CLI does not care; viewers do).
std::string Extension(const std::string& format) {
  static const std::map<std::string, std::string> known = {
      {"obj", "obj"}, {"geojson", "geojson"}, {"ply", "ply"},     {"stl", "stl"},
      {"glb", "glb"}, {"gpkg", "gpkg"},       {"landxml", "xml"}, {"vdb", "vdb"}};
  const auto it = known.find(format);
  return it == known.end() ? format : it->second;
}

std::string FirstLine(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// `tinbase export STORE --surface terrain --format F -o OUT` in a child, timed (its stderr goes
// to a file, so it draws no progress bar).
Export RunExport(const std::string& cli, const std::string& store, const std::string& format,
                 const std::string& dir) {
  const std::string output = dir + "/export." + Extension(format);
  const std::string errors = dir + "/export.stderr";
  std::filesystem::remove(output);
  std::fflush(stdout);  // or the child's freopen writes our buffered lines a second time
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen(errors.c_str(), "w", stderr))
      _exit(126);
    execl(cli.c_str(), "tinbase", "export", store.c_str(), "--surface", kStore1e6Surface,
          "--format", format.c_str(), "-o", output.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  Export e;
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  e.peak_rss_kib = usage.ru_maxrss;
  const auto secs = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
  };
  e.cpu_seconds = secs(usage.ru_utime) + secs(usage.ru_stime);
  e.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!e.ok) e.error = FirstLine(errors);
  std::error_code ec;
  const auto size = std::filesystem::file_size(output, ec);
  e.bytes = ec ? 0 : static_cast<int64_t>(size);
  std::filesystem::remove(output);
  return e;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

std::vector<std::string> Split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

int64_t TriangleCount(const std::string& store_path) {
  auto store = Store::Open(store_path, Store::Access::kReadOnly);
  if (!store.ok()) return 0;
  SurfaceStore surfaces(**store);
  auto surface = surfaces.Find(kStore1e6Surface);
  if (!surface.ok()) return 0;
  auto loaded = surfaces.Load(*surface);
  return loaded.ok() ? static_cast<int64_t>(loaded->tin.triangles.size()) : 0;
}

int Run(const std::string& cli, const std::string& dir, const std::vector<std::string>& formats,
        int rounds) {
  const std::string store = Store1e6(dir);
  const int64_t triangles = TriangleCount(store);
  std::printf("store %s: %lld triangles\n", store.c_str(), static_cast<long long>(triangles));
  std::map<std::string, std::vector<Export>> runs;
  std::printf("round,format,ok,seconds,cpu_seconds,bytes,peak_rss_mib\n");
  for (int round = 1; round <= rounds; ++round) {
    for (size_t k = 0; k < formats.size(); ++k) {
      const std::string& f = formats[(k + static_cast<size_t>(round) - 1) % formats.size()];
      const Export e = RunExport(cli, store, f, dir);
      std::printf("%d,%s,%s,%.3f,%.3f,%lld,%.0f%s%s\n", round, f.c_str(), e.ok ? "yes" : "no",
                  e.seconds, e.cpu_seconds, static_cast<long long>(e.bytes),
                  static_cast<double>(e.peak_rss_kib) / 1024, e.ok ? "" : ",", e.error.c_str());
      std::fflush(stdout);
      runs[f].push_back(e);
    }
  }
  std::printf(
      "\nsummary (median of %d rounds): format, wall s, CPU s, bytes, bytes per triangle, "
      "peak RSS MiB, CPU time / OBJ's (per round), wall time / OBJ's (per round), bytes / OBJ\n",
      rounds);
  const auto list = [](const std::vector<double>& values) {
    std::string text;
    for (double x : values) {
      char one[16];
      std::snprintf(one, sizeof one, "%s%.2f", text.empty() ? "" : " ", x);
      text += one;
    }
    return text;
  };
  const std::vector<Export>* obj = runs.count("obj") ? &runs["obj"] : nullptr;
  for (const std::string& f : formats) {
    const std::vector<Export>& r = runs[f];
    if (!r.front().ok) {
      std::printf("%s,not available: %s\n", f.c_str(), r.front().error.c_str());
      continue;
    }
    std::vector<double> wall, cpu, rss, cpu_over_obj, wall_over_obj;
    for (size_t i = 0; i < r.size(); ++i) {
      wall.push_back(r[i].seconds);
      cpu.push_back(r[i].cpu_seconds);
      rss.push_back(static_cast<double>(r[i].peak_rss_kib) / 1024);
      if (obj && (*obj)[i].ok) {
        cpu_over_obj.push_back(r[i].cpu_seconds / (*obj)[i].cpu_seconds);
        wall_over_obj.push_back(r[i].seconds / (*obj)[i].seconds);
      }
    }
    const double bytes = static_cast<double>(r.front().bytes);
    const double obj_bytes = obj ? static_cast<double>(obj->front().bytes) : 0;
    std::printf("%s,%.2f,%.2f,%.0f,%.1f,%.0f,%s,%s,%.2f\n", f.c_str(), Median(wall), Median(cpu),
                bytes, bytes / static_cast<double>(triangles), Median(rss),
                list(cpu_over_obj).c_str(), list(wall_over_obj).c_str(),
                obj_bytes > 0 ? bytes / obj_bytes : 0);
  }
  return 0;
}

}  // namespace
}  // namespace tinbase

int main(int argc, char** argv) {
  CLI::App app{"export_bench: tinbase export of the ~1e6-triangle store to each format"};
  std::string dir;
  std::string formats = "obj,geojson,ply,stl,glb,gpkg,landxml";
  int rounds = 3;
  std::string cli = TINBASE_CLI;
  app.add_option("--dir", dir, "Where the store is (built there once) and exports go")->required();
  app.add_option("--formats", formats, "Comma-separated formats, one row each");
  app.add_option("--rounds", rounds, "Rounds (each exports every format once)");
  app.add_option("--cli", cli, "The tinbase binary to run (default: this build's)");
  CLI11_PARSE(app, argc, argv);
  GDALAllRegister();
  return tinbase::Run(cli, dir, tinbase::Split(formats), rounds);
}
