// ExportFormat: the file formats `tinbase export` writes, parsed from what a user typed once, at
// the edge (the --format option, or the output file's extension), so code past it switches on
// the enum. Formats are added in one place: the table in export_format.cc. Thread-safety: pure
// functions over constant data.
#pragma once

#include <optional>
#include <string>

#include "core/base/status.h"

namespace tinbase {

enum class ExportFormat {
  kObj,      // Wavefront OBJ, text (core/export/obj_writer.h)
  kPly,      // binary little-endian PLY with tag and visibility per face (ply_writer.h)
  kStl,      // binary STL, float32 relative to a recorded origin (stl_writer.h)
  kGlb,      // glTF 2.0 binary in a local east-north-up frame (glb_writer.h)
  kGeoJson,  // one 3D polygon feature per triangle, through OGR (geojson_writer.h)
};

// The spelling users give and the writers' names use: "obj", "ply", "stl", "glb", "geojson".
const char* ExportFormatName(ExportFormat format);

// Every format's name, comma separated, for messages and --help.
std::string ExportFormatList();

// The format `name` spells (lower case, exactly). InvalidArgument "unknown export format 'x'
// (expected one of: obj, ply, ...)" otherwise.
Result<ExportFormat> ParseExportFormat(const std::string& name);

// The format an output path's extension stands for (case-insensitive: ".obj", ".ply", ".stl",
// ".glb", ".geojson" or ".json"); nullopt for any other or no extension.
std::optional<ExportFormat> ExportFormatFromPath(const std::string& path);

}  // namespace tinbase
