// The `export` command's LandXML and OpenVDB cases (--format landxml, --format vdb), kept apart
// from export_commands.cc so that file needs only a dispatch line for them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "db/query/surface_selection.h"

namespace tinbase::cli {

struct LandXmlVdbExportArgs {
  std::string store;
  std::string surface;
  std::string output;
  SurfaceFilter filter;         // --bbox, --feature, --visible-only, --tag
  std::string base;             // vdb: the lower surface of a thickness (fog volume)
  double voxel = 0;             // vdb: voxel size (0: the longer side / 512)
  std::optional<double> floor;  // vdb level set: the floor's z
};

// `--format landxml`: the whole surface with its features and constraint owners, or (with a
// selection) the selected triangles alone. Returns the exit code.
int RunLandXmlExport(const LandXmlVdbExportArgs& args);
// `--format vdb`: a level set of the surface, or with --base a fog volume of the thickness
// between --base and --surface. Prints the grid's volume. Returns the exit code.
int RunVdbExport(const LandXmlVdbExportArgs& args);

}  // namespace tinbase::cli
