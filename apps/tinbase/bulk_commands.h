// Which tinbase commands start again on huge-page malloc (core/base/huge_page_malloc.h).
//
// Two kinds: the bulk commands, decided from the command line before anything runs, and the
// whole-surface reads (`export --surface`, `check`) of a large store, decided by their handlers
// from the store's file size before they open it. On the 1e6-triangle benchmark store (117 MB),
// restart included, huge pages took `export` from 1.6 to 1.2 s, `check` from 3.1-3.3 to 2.4-2.6 s
// and `check --full` from 4.2-4.4 to 3.2-3.4 s; on a 1e5-triangle store (11 MB) `check` gained less
// than the restart costs.
//
// The second start loads the program's ~120 shared libraries again: about 0.14 s on the CI VM,
// half the run time of a query or a polygon edit. It pays where millions of points are
// triangulated and their memory is touched fresh: a 3 M-point `points import` took 10.7-11.7 s
// with it and 14.2-14.9 s without. TIN builds over large DEMs touch as much (an edge collapse of
// a 2237^2 DEM held 1.7 GB), and next to such a run the restart is noise; a small build shows it
// (a vip build of that DEM: 0.43-0.49 s with, 0.35-0.40 s without). A `dem import` of that DEM,
// a 1178-polygon map loaded feature by feature and the queries tried (info, locate) ran as fast
// or faster without.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

#include "core/base/huge_page_malloc.h"

namespace tinbase::cli {

// True for `tinbase points ...`, `tinbase tin ...` and `tinbase dem from-contours ...` (a CDT
// of contour lines); argv as main gets it.
inline bool TriangulatesInBulk(int argc, const char* const* argv) {
  if (argc < 2) return false;
  const std::string_view command = argv[1];
  if (command == "points" || command == "tin") return true;
  return command == "dem" && argc >= 3 && std::string_view(argv[2]) == "from-contours";
}

// A store file from this size on is read whole on huge pages: about 3e5 triangles.
inline constexpr std::uintmax_t kLargeStoreBytes = std::uintmax_t{32} << 20;

// True when `store` is a file of at least kLargeStoreBytes (false when it is missing).
inline bool IsLargeStore(const std::string& store) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(store, ec);
  return !ec && bytes >= kLargeStoreBytes;
}

// For a command that reads whole surfaces of `store`: starts the process again on huge-page
// malloc when the store is large (and the restart is allowed). Call before opening the store.
inline void RestartOnHugePagesIfLarge(const std::string& store) {
  if (IsLargeStore(store)) RestartWithHugePageMalloc();
}

}  // namespace tinbase::cli
