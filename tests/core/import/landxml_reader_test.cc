// ReadLandXml accepts other software's TINs (any point ids, clockwise faces, no `n`) and
// rejects bad LandXML with a message naming the file, the line and the element.
#include "core/import/landxml_reader.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <fstream>
#include <string>

#include "core/export/landxml_writer.h"
#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// A unit square of two faces, one element a line: <P> on lines 6-9, <F> on lines 12-13.
std::string Square(const std::string& face1 = R"(<F n="0 0 2">10 20 30</F>)",
                   const std::string& p4 = R"(<P id="40">1 0 4</P>)") {
  std::string text =
      "<?xml version=\"1.0\"?>\n"
      "<LandXML xmlns=\"http://www.landxml.org/schema/LandXML-1.2\" version=\"1.2\">\n"
      "<Surfaces>\n"
      "<Surface name=\"sq\">\n"
      "<Definition surfType=\"TIN\"><Pnts>\n"
      "<P id=\"10\">0 0 1</P>\n"
      "<P id=\"20\">0 1 2</P>\n"
      "<P id=\"30\">1 1 3</P>\n";
  text += p4;
  text += "\n</Pnts>\n<Faces>\n";
  text += face1;
  text +=
      "\n<F n=\"1 0 0\">10 30 40</F>\n"
      "</Faces></Definition>\n"
      "</Surface>\n"
      "</Surfaces>\n"
      "</LandXML>\n";
  return text;
}

class LandXmlReaderTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& text) {
    std::string name = std::to_string(++n_);
    name += ".xml";
    const std::string path = dir_.Path(name);
    std::ofstream(path) << text;
    return path;
  }
  // Reading `text` fails with a message holding each of `parts`.
  void ExpectRejected(const std::string& text, const std::vector<std::string>& parts) {
    const std::string path = Write(text);
    auto r = ReadLandXml(path);
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_EQ(r.status().message().rfind(path, 0), 0u) << r.status().message();
    for (const std::string& part : parts)
      EXPECT_NE(r.status().message().find(part), std::string::npos)
          << "expected '" << part << "' in: " << r.status().message();
  }
  TempDir dir_;
  int n_ = 0;
};

TEST_F(LandXmlReaderTest, ReadsAForeignSquare) {
  auto r = ReadLandXml(Write(Square()));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->name, "sq");
  EXPECT_EQ(r->kind, "free");  // no tinbase extension: no Delaunay claim
  ASSERT_EQ(r->tin.vertices.size(), 4u);
  EXPECT_EQ(r->tin.vertices[1].x, 1);  // "0 1 2" is northing 0, easting 1
  EXPECT_EQ(r->tin.vertices[1].y, 0);
  EXPECT_EQ(r->tin.vertices[1].z, 2);
  ASSERT_EQ(r->tin.triangles.size(), 2u);
  // Face 1 (10 20 30) is counter-clockwise; across (30 10) lies face 2: tinbase's neighbour
  // opposite vertex 20.
  EXPECT_EQ(r->tin.triangles[0].n[1], 1);
  EXPECT_EQ(r->tin.triangles[1].n[2], 0);
}

TEST_F(LandXmlReaderTest, TurnsClockwiseFacesAndComputesMissingNeighbours) {
  // Face 1 listed clockwise, no n anywhere.
  std::string text = Square("<F>10 30 20</F>");
  text.replace(text.find("<F n=\"1 0 0\">"), 13, "<F>");
  auto r = ReadLandXml(Write(text));
  ASSERT_TRUE(r.ok()) << r.status().message();
  const TinTriangle& t = r->tin.triangles[0];
  EXPECT_EQ(t.v, (std::array<uint32_t, 3>{0, 1, 2}));  // turned counter-clockwise
  EXPECT_EQ(t.n[1], 1);
  EXPECT_EQ(r->tin.triangles[1].n[2], 0);
}

TEST_F(LandXmlReaderTest, RejectsWhatIsNotLandXml) {
  ExpectRejected("this is not XML\n", {"line 1", "not well-formed XML"});
  ExpectRejected("<?xml version=\"1.0\"?>\n<LandXML>\n<Surfaces>\n</LandXML>\n",
                 {"line 4", "not well-formed XML"});
  ExpectRejected("<?xml version=\"1.0\"?>\n<Other/>\n", {"line 2, <Other>", "not a LandXML file"});
  ExpectRejected("<?xml version=\"1.0\"?>\n<LandXML version=\"1.2\"><Surfaces/></LandXML>\n",
                 {"no Surfaces/Surface/Definition"});
}

TEST_F(LandXmlReaderTest, RejectsBadPointsAndFacesNamingTheLine) {
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 99</F>)"),
                 {"line 12, <F>", "face refers to point 99, which is not in Pnts"});
  ExpectRejected(Square(R"(<F>10 20 x</F>)"), {"line 12, <F>", "'x' is not a whole number"});
  ExpectRejected(Square(R"(<F>10 20</F>)"), {"line 12, <F>", "expected 3"});
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 30</F>)", R"(<P id="40">1 zero 4</P>)"),
                 {"line 9, <P>", "'zero' is not a number"});
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 30</F>)", R"(<P id="40">1 0</P>)"),
                 {"line 9, <P>", "northing easting elevation"});
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 30</F>)", R"(<P id="40">1 0 nan</P>)"),
                 {"line 9, <P>", "'nan' is not a number"});
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 30</F>)", R"(<P id="10">1 0 4</P>)"),
                 {"line 9, <P>", "point id 10 is used twice (first at line 6)"});
  ExpectRejected(Square(R"(<F n="0 0 2">10 20 30</F>)", R"(<P>1 0 4</P>)"),
                 {"line 9, <P>", "needs an id"});
}

TEST_F(LandXmlReaderTest, RejectsFacesThatDoNotFormATriangulation) {
  ExpectRejected(Square(R"(<F n="0 1 0">10 20 30</F>)"),
                 {"line 12, <F>", "attribute n names face 1 across edge 2"});
  ExpectRejected(Square(R"(<F n="0 2">10 20 30</F>)"), {"line 12, <F>", "attribute n"});
  ExpectRejected(Square(R"(<F>10 20 20</F>)"), {"line 12, <F>", "collinear"});
  // The second face repeats the first's edge (10 30) in the same direction.
  ExpectRejected(Square(R"(<F>10 30 40</F>)"), {"line 13, <F>", "shares an edge"});
  ExpectRejected(Square(R"(<F i="2">10 20 30</F>)"), {"line 12, <F>", "attribute i"});
  ExpectRejected(Square(R"(<F xmlns:tb="urn:tinbase:landxml:1" tb:tag="0">10 20 30</F>)"),
                 {"line 12, <F>", "tb:tag 0 is not one of the 0 tags"});
}

// Property: a LandXML file damaged at random (bytes replaced, cut out or repeated) is either
// read into a consistent TIN or rejected as bad input naming the file; never a crash, never
// another kind of error. RapidCheck prints the seed of a failure.
RC_GTEST_PROP(LandXmlReaderProperty, DamagedFilesAreReadConsistentlyOrRejected, ()) {
  static const std::string original = [] {
    TempDir dir;
    LandXmlSurface s;
    s.name = "grid";
    s.tin = testing::MakeGridTin(4, 3, 10.5, 1000, 2000, [](double x, double y) { return x - y; });
    s.tin.tags = {"a"};
    s.tin.triangles[3].tag = 0;
    s.tin.triangles[5].visible = false;
    EXPECT_TRUE(WriteLandXml(s, dir.Path("g.xml")).ok());
    std::ifstream in(dir.Path("g.xml"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  std::string text = original;
  const int edits = *rc::gen::inRange(1, 4);
  for (int e = 0; e < edits && !text.empty(); ++e) {
    const size_t at = *rc::gen::inRange<size_t>(0, text.size());
    const size_t len = std::min(text.size() - at, *rc::gen::inRange<size_t>(1, 40));
    switch (*rc::gen::inRange(0, 3)) {
      case 0: {
        static const std::string alphabet = "<>/\"= 0123456789-.eE&;xnPFi";
        text[at] = alphabet[*rc::gen::inRange<size_t>(0, alphabet.size())];
        break;
      }
      case 1:
        text.erase(at, len);
        break;
      default:
        text.insert(at, text.substr(at, len));
    }
  }
  TempDir dir;
  const std::string path = dir.Path("damaged.xml");
  std::ofstream(path) << text;
  auto r = ReadLandXml(path);
  if (!r.ok()) {
    RC_ASSERT(r.status().code() == StatusCode::kInvalidArgument);
    RC_ASSERT(r.status().message().rfind(path, 0) == 0u);
    return;
  }
  const Tin& tin = r->tin;
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    for (int k = 0; k < 3; ++k) {
      RC_ASSERT(tri.v[k] < tin.vertices.size());
      if (tri.n[k] == kNoNeighbour) continue;
      RC_ASSERT(static_cast<size_t>(tri.n[k]) < tin.triangles.size());
      const auto& back = tin.triangles[tri.n[k]].n;
      RC_ASSERT(std::find(back.begin(), back.end(), static_cast<int32_t>(t)) != back.end());
    }
    RC_ASSERT(tri.tag == kNoTag || static_cast<size_t>(tri.tag) < tin.tags.size());
  }
}

}  // namespace
}  // namespace tinbase
