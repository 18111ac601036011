// Which tinbase commands start again on huge-page malloc (core/base/huge_page_malloc.h).
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

#include <string_view>

namespace tinbase::cli {

// True for `tinbase points ...`, `tinbase tin ...` and `tinbase dem from-contours ...` (a CDT
// of contour lines); argv as main gets it.
inline bool TriangulatesInBulk(int argc, const char* const* argv) {
  if (argc < 2) return false;
  const std::string_view command = argv[1];
  if (command == "points" || command == "tin") return true;
  return command == "dem" && argc >= 3 && std::string_view(argv[2]) == "from-contours";
}

}  // namespace tinbase::cli
