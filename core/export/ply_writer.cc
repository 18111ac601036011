#include "core/export/ply_writer.h"

#include <algorithm>
#include <fstream>
#include <limits>
#include <vector>

#include "core/export/binary_out.h"
#include "core/export/crs_text.h"

namespace tinbase {

namespace {

// A header comment runs to the end of its line, so a value must not contain a line break.
std::string OneLine(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return text;
}

// tin tag index -> written tag index (dense, first use), and the written tags' values.
struct TagNumbering {
  std::vector<int32_t> written;
  std::vector<std::string> values;
};

TagNumbering NumberTags(const Tin& tin, const MeshSelection& s) {
  TagNumbering n;
  n.written.assign(tin.tags.size(), kNoTag);
  for (uint32_t t : s.triangles) {
    const int32_t tag = tin.triangles[t].tag;
    if (tag == kNoTag || n.written[static_cast<size_t>(tag)] != kNoTag) continue;
    n.written[static_cast<size_t>(tag)] = static_cast<int32_t>(n.values.size());
    n.values.push_back(tin.tags[static_cast<size_t>(tag)]);
  }
  return n;
}

std::string Header(const Crs* crs, const MeshSelection& s, const TagNumbering& tags) {
  std::string h = "ply\nformat binary_little_endian 1.0\n";
  h += "comment tinbase surface: x y z in the CRS below, faces counter-clockwise seen from above\n";
  h += "comment face tag: -1 untagged, else K of a 'comment tag K VALUE' line; visible: 1 or 0\n";
  if (crs != nullptr) {
    h += "comment crs " + OneLine(crs->Label()) + "\n";
    h += "comment crs_wkt " + OneLineWkt(*crs) + "\n";
  } else {
    h += "comment crs none\n";
  }
  for (size_t k = 0; k < tags.values.size(); ++k)
    h += "comment tag " + std::to_string(k) + " " + OneLine(tags.values[k]) + "\n";
  h += "element vertex " + std::to_string(s.vertices.size()) + "\n";
  h += "property double x\nproperty double y\nproperty double z\n";
  h += "element face " + std::to_string(s.triangles.size()) + "\n";
  h += "property list uchar int vertex_indices\nproperty int tag\nproperty uchar visible\n";
  h += "end_header\n";
  return h;
}

}  // namespace

Status WritePly(const Tin& tin, const Crs* crs, const MeshSelection& s, const std::string& path) {
  if (s.vertices.size() > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
    return Status::InvalidArgument(path + ": " + std::to_string(s.vertices.size()) +
                                   " vertices are more than PLY's int indices reach");
  const TagNumbering tags = NumberTags(tin, s);
  BinaryOut out;
  out.PutText(Header(crs, s, tags));
  out.Reserve(out.bytes().size() + s.vertices.size() * 24 + s.triangles.size() * 18);
  for (uint32_t v : s.vertices) {
    const TinVertex& p = tin.vertices[v];
    out.Put(p.x), out.Put(p.y), out.Put(p.z);
  }
  for (uint32_t t : s.triangles) {
    const TinTriangle& tri = tin.triangles[t];
    out.Put(uint8_t{3});
    for (uint32_t v : tri.v) out.Put(static_cast<int32_t>(s.output_index[v]));
    out.Put(tri.tag == kNoTag ? kNoTag : tags.written[static_cast<size_t>(tri.tag)]);
    out.Put(static_cast<uint8_t>(tri.visible ? 1 : 0));
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Status::IOError(path + ": cannot open for writing");
  file.write(out.bytes().data(), static_cast<std::streamsize>(out.bytes().size()));
  file.close();
  if (!file) return Status::IOError(path + ": write failed");
  return Status::Ok();
}

}  // namespace tinbase
