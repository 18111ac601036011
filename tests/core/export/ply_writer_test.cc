// The PLY writer's files read back through CGAL's PLY reader (a reader we did not write): the
// same vertices bit for bit, faces in order and counter-clockwise, tag and visible per face as
// properties, tag names and CRS in the header comments.
#include "core/export/ply_writer.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/export/mesh_selection.h"
#include "tests/core/export/sample_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

struct PlyFile {
  Mesh mesh;
  std::string comments;
};

PlyFile ReadPly(const std::string& path) {
  PlyFile out;
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(CGAL::IO::read_PLY(in, out.mesh, out.comments, /*verbose=*/true)) << path;
  return out;
}

// The tag names from the "tag K VALUE" comment lines, by K.
std::vector<std::string> TagComments(const std::string& comments) {
  std::vector<std::string> tags;
  std::istringstream in(comments);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("tag ", 0) != 0) continue;
    const size_t space = line.find(' ', 4);
    EXPECT_EQ(std::stoul(line.substr(4, space - 4)), tags.size()) << line;
    tags.push_back(line.substr(space + 1));
  }
  return tags;
}

TEST(WritePly, ReadsBackThroughCgalWithTagsVisibilityAndExactCoordinates) {
  const Tin tin = testing::SampleExportTin();
  auto crs = Crs::FromUserInput("EPSG:32632");
  ASSERT_TRUE(crs.ok());
  testing::TempDir dir;
  const std::string path = dir.Path("s.ply");
  ASSERT_TRUE(WritePly(tin, &*crs, SelectTriangles(tin, false), path).ok());

  PlyFile ply = ReadPly(path);
  ASSERT_EQ(ply.mesh.number_of_vertices(), tin.vertices.size());
  ASSERT_EQ(ply.mesh.number_of_faces(), tin.triangles.size());
  for (size_t v = 0; v < tin.vertices.size(); ++v) {
    const auto& p = ply.mesh.point(Mesh::Vertex_index(static_cast<uint32_t>(v)));
    EXPECT_EQ(p.x(), tin.vertices[v].x);
    EXPECT_EQ(p.y(), tin.vertices[v].y);
    EXPECT_EQ(p.z(), tin.vertices[v].z);
  }
  auto [tag, has_tag] = ply.mesh.property_map<Mesh::Face_index, int32_t>("f:tag");
  auto [visible, has_visible] = ply.mesh.property_map<Mesh::Face_index, uint8_t>("f:visible");
  ASSERT_TRUE(has_tag);
  ASSERT_TRUE(has_visible);
  const std::vector<std::string> names = TagComments(ply.comments);
  ASSERT_EQ(names.size(), 2u);
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const Mesh::Face_index f(static_cast<uint32_t>(t));
    const TinTriangle& tri = tin.triangles[t];
    EXPECT_EQ(visible[f], tri.visible ? 1 : 0) << t;
    if (tri.tag == kNoTag) {
      EXPECT_EQ(tag[f], -1) << t;
    } else {
      ASSERT_GE(tag[f], 0);
      EXPECT_EQ(names[static_cast<size_t>(tag[f])], tin.tags[static_cast<size_t>(tri.tag)]);
    }
    // Same corners in the same counter-clockwise order (up to rotation of the cycle).
    std::vector<uint32_t> corners;
    for (auto v : CGAL::vertices_around_face(ply.mesh.halfedge(f), ply.mesh)) corners.push_back(v);
    ASSERT_EQ(corners.size(), 3u);
    const auto start = std::find(corners.begin(), corners.end(), tri.v[0]);
    ASSERT_NE(start, corners.end());
    std::rotate(corners.begin(), start, corners.end());
    EXPECT_EQ(corners[1], tri.v[1]);
    EXPECT_EQ(corners[2], tri.v[2]);
  }
  EXPECT_NE(ply.comments.find("crs EPSG:32632"), std::string::npos) << ply.comments;
  const size_t wkt_at = ply.comments.find("crs_wkt ");
  ASSERT_NE(wkt_at, std::string::npos);
  const std::string wkt =
      ply.comments.substr(wkt_at + 8, ply.comments.find('\n', wkt_at) - wkt_at - 8);
  auto back = Crs::FromWkt(wkt);
  ASSERT_TRUE(back.ok()) << wkt;
  EXPECT_TRUE(back->IsSame(*crs));
}

TEST(WritePly, VisibleOnlyWritesTheVisibleFacesAndTheTagsTheyUse) {
  Tin tin = testing::SampleExportTin();
  tin.tags.push_back("unused");
  testing::TempDir dir;
  const std::string path = dir.Path("v.ply");
  const MeshSelection s = SelectTriangles(tin, true);
  ASSERT_TRUE(WritePly(tin, nullptr, s, path).ok());
  PlyFile ply = ReadPly(path);
  EXPECT_EQ(ply.mesh.number_of_faces(), s.triangles.size());
  EXPECT_EQ(ply.mesh.number_of_vertices(), s.vertices.size());
  EXPECT_LT(s.triangles.size(), tin.triangles.size());
  auto [visible, has_visible] = ply.mesh.property_map<Mesh::Face_index, uint8_t>("f:visible");
  ASSERT_TRUE(has_visible);
  for (auto f : ply.mesh.faces()) EXPECT_EQ(visible[f], 1);
  EXPECT_EQ(TagComments(ply.comments).size(), 2u);  // "unused" is not listed
  EXPECT_NE(ply.comments.find("crs none"), std::string::npos);
}

}  // namespace
}  // namespace tinbase
