#include "core/export/obj_writer.h"

#include <charconv>
#include <fstream>
#include <system_error>

#include "core/export/crs_text.h"

namespace tinbase {

namespace {

// Shortest text that reads back as exactly `value` (std::to_chars without a precision).
void AppendNumber(std::string& out, double value) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

}  // namespace

Status WriteObj(const Tin& tin, const Crs* crs, const MeshSelection& s, const std::string& path) {
  std::string text =
      "# tinbase surface (Wavefront OBJ): x y z per vertex, faces counter-clockwise "
      "seen from above\n";
  if (crs != nullptr) {
    text += "# crs: " + crs->Label() + "\n# crs_wkt: " + OneLineWkt(*crs) + "\n";
  } else {
    text += "# crs: none\n";
  }
  text += "# vertices: " + std::to_string(s.vertices.size()) +
          ", triangles: " + std::to_string(s.triangles.size()) + "\n";
  text.reserve(text.size() + s.vertices.size() * 64 + s.triangles.size() * 32);
  for (uint32_t v : s.vertices) {
    const TinVertex& p = tin.vertices[v];
    text += "v ";
    AppendNumber(text, p.x);
    text += ' ';
    AppendNumber(text, p.y);
    text += ' ';
    AppendNumber(text, p.z);
    text += '\n';
  }
  for (uint32_t t : s.triangles) {
    text += 'f';
    for (uint32_t v : tin.triangles[t].v) text += ' ' + std::to_string(s.output_index[v] + 1);
    text += '\n';
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Status::IOError(path + ": cannot open for writing");
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) return Status::IOError(path + ": write failed");
  return Status::Ok();
}

}  // namespace tinbase
