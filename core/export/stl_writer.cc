#include "core/export/stl_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "core/export/binary_out.h"

namespace tinbase {

namespace {

constexpr size_t kHeaderBytes = 80;

std::string HeaderText(const Crs* crs, const StlOrigin& origin) {
  char text[kHeaderBytes + 1];
  std::snprintf(text, sizeof text, "tinbase STL origin %.17g %.17g 0 crs %s", origin.x, origin.y,
                crs != nullptr ? crs->Label().c_str() : "none");
  std::string header = text;
  header.resize(kHeaderBytes, ' ');
  return header;
}

}  // namespace

StlOrigin StlOriginOf(const Tin& tin, const MeshSelection& s) {
  if (s.vertices.empty()) return {};
  double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
  double min_y = min_x, max_y = max_x;
  for (uint32_t v : s.vertices) {
    const TinVertex& p = tin.vertices[v];
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  return {std::round(min_x / 2 + max_x / 2), std::round(min_y / 2 + max_y / 2)};
}

Status WriteStl(const Tin& tin, const Crs* crs, const MeshSelection& s, const std::string& path) {
  if (s.triangles.size() > std::numeric_limits<uint32_t>::max())
    return Status::InvalidArgument(path + ": " + std::to_string(s.triangles.size()) +
                                   " triangles are more than binary STL can count");
  const StlOrigin origin = StlOriginOf(tin, s);
  BinaryOut out;
  out.Reserve(kHeaderBytes + 4 + s.triangles.size() * 50);
  out.PutText(HeaderText(crs, origin));
  out.Put(static_cast<uint32_t>(s.triangles.size()));
  for (uint32_t t : s.triangles) {
    std::array<std::array<float, 3>, 3> corner{};
    for (int k = 0; k < 3; ++k) {
      const TinVertex& p = tin.vertices[tin.triangles[t].v[k]];
      corner[k] = {static_cast<float>(p.x - origin.x), static_cast<float>(p.y - origin.y),
                   static_cast<float>(p.z)};
    }
    // The normal of the corners as written, so a reader recomputing it finds the same one.
    const double ux = corner[1][0] - corner[0][0], uy = corner[1][1] - corner[0][1],
                 uz = corner[1][2] - corner[0][2];
    const double vx = corner[2][0] - corner[0][0], vy = corner[2][1] - corner[0][1],
                 vz = corner[2][2] - corner[0][2];
    double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
    if (length > 0) nx /= length, ny /= length, nz /= length;
    out.Put(static_cast<float>(nx)), out.Put(static_cast<float>(ny)),
        out.Put(static_cast<float>(nz));
    for (const auto& c : corner) out.Put(c[0]), out.Put(c[1]), out.Put(c[2]);
    out.Put(uint16_t{0});
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Status::IOError(path + ": cannot open for writing");
  file.write(out.bytes().data(), static_cast<std::streamsize>(out.bytes().size()));
  file.close();
  if (!file) return Status::IOError(path + ": write failed");
  return Status::Ok();
}

}  // namespace tinbase
