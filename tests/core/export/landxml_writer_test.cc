// WriteLandXml writes LandXML 1.2 that libxml2's own XPath reads with the structure LandXML
// promises (Units, CoordinateSystem, P in "y x z", F with n and i, breaklines and boundaries),
// and that ReadLandXml brings back bit for bit: vertices, triangles, neighbours, visibility,
// tags, vertex kinds, features and constraint owners.
#include "core/export/landxml_writer.h"

#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/xpath.h>
#include <libxml/xpathInternals.h>

#include <cmath>
#include <memory>
#include <sstream>

#include "core/import/landxml_reader.h"
#include "tests/support/grid_tin.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

// A 12 x 9 grid with irrational-looking coordinates (so shortest round-trip printing matters),
// invisible triangles, two tags, every vertex kind, three features (a fill polygon with a hole,
// a clip polygon, a breakline) and constraints with and without owners.
LandXmlSurface SampleSurface() {
  LandXmlSurface s;
  s.name = "terrain & <rock>";  // needs escaping
  s.kind = "delaunay";
  s.method = "greedy";
  s.tolerance = 0.1 + 0.2;
  s.dem = "srtm";
  s.crs_wkt = "GEOGCS[\"x\"]";  // the writer does not interpret it
  s.epsg = 32632;
  s.crs_name = "EPSG:32632";
  s.tin = testing::MakeGridTin(
      12, 9, 30.123456789012345, 612345.678901234, 5171234.56789012, [](double x, double y) {
        return 1000.0 + std::sin(x / 77.7) * 123.456789 + std::cos(y / 51.3) / 3.0;
      });
  s.tin.tags = {"granite", "schist \"blue\""};
  for (size_t t = 0; t < s.tin.triangles.size(); ++t) {
    if (t % 7 == 3) s.tin.triangles[t].visible = false;
    if (t % 5 == 0) s.tin.triangles[t].tag = static_cast<int32_t>((t / 5) % 2);
  }
  for (size_t v = 0; v < s.tin.vertices.size(); ++v)
    s.tin.vertices[v].kind = static_cast<VertexKind>(v % 5);
  const double x0 = 612345.678901234, y0 = 5171234.56789012;
  LandXmlFeature fill;
  fill.name = "granite";
  fill.mode = FeatureMode::kFill;
  fill.tag = "granite";
  fill.attributes = R"({"code":"A-b","n":3})";
  fill.polygons.push_back({{{x0 + 10.1, y0 + 10.3},
                            {x0 + 200.7, y0 + 10.3},
                            {x0 + 200.7, y0 + 150.9},
                            {x0 + 10.1, y0 + 150.9}},
                           {{{x0 + 50.5, y0 + 50.5},
                             {x0 + 50.5, y0 + 90.25},
                             {x0 + 90.125, y0 + 90.25},
                             {x0 + 90.125, y0 + 50.5}}}});
  LandXmlFeature clip;
  clip.name = "feature 2";
  clip.mode = FeatureMode::kClip;
  clip.level = 1.0 / 3.0;
  clip.polygons.push_back({{{x0, y0}, {x0 + 300, y0}, {x0 + 300, y0 + 250}, {x0, y0 + 250}}, {}});
  LandXmlFeature fault;
  fault.name = "fault";
  fault.mode = FeatureMode::kBreakline;
  fault.lines.push_back(
      {{x0 + 1.0 / 7.0, y0 + 2.0 / 7.0}, {x0 + 99.9, y0 + 77.7}, {x0 + 150, y0 + 1}});
  s.features = {fill, clip, fault};
  s.constraints = {{0, 1, 0}, {1, 2, 0}, {1, 2, 1}, {14, 15, std::nullopt}, {20, 33, 2}};
  return s;
}

void ExpectSame(const LandXmlSurface& a, const LandXmlSurface& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.tolerance, b.tolerance);
  EXPECT_EQ(a.dem, b.dem);
  EXPECT_EQ(a.crs_wkt, b.crs_wkt);
  EXPECT_EQ(a.epsg, b.epsg);
  ASSERT_EQ(a.tin.vertices.size(), b.tin.vertices.size());
  for (size_t i = 0; i < a.tin.vertices.size(); ++i) {
    const TinVertex &p = a.tin.vertices[i], &q = b.tin.vertices[i];
    ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z && p.kind == q.kind) << "vertex " << i;
  }
  ASSERT_EQ(a.tin.triangles.size(), b.tin.triangles.size());
  for (size_t t = 0; t < a.tin.triangles.size(); ++t) {
    const TinTriangle &p = a.tin.triangles[t], &q = b.tin.triangles[t];
    ASSERT_EQ(p.v, q.v) << "triangle " << t;
    ASSERT_EQ(p.n, q.n) << "triangle " << t;
    ASSERT_EQ(p.visible, q.visible) << "triangle " << t;
    ASSERT_EQ(p.tag, q.tag) << "triangle " << t;
  }
  EXPECT_EQ(a.tin.tags, b.tin.tags);
  ASSERT_EQ(a.constraints.size(), b.constraints.size());
  for (size_t i = 0; i < a.constraints.size(); ++i) {
    EXPECT_EQ(a.constraints[i].a, b.constraints[i].a);
    EXPECT_EQ(a.constraints[i].b, b.constraints[i].b);
    EXPECT_EQ(a.constraints[i].feature, b.constraints[i].feature);
  }
  ASSERT_EQ(a.features.size(), b.features.size());
  for (size_t i = 0; i < a.features.size(); ++i) {
    const LandXmlFeature &f = a.features[i], &g = b.features[i];
    EXPECT_EQ(f.name, g.name);
    EXPECT_EQ(f.mode, g.mode);
    EXPECT_EQ(f.tag, g.tag);
    EXPECT_EQ(f.level, g.level);
    EXPECT_EQ(f.attributes, g.attributes);
    ASSERT_EQ(f.polygons.size(), g.polygons.size());
    for (size_t p = 0; p < f.polygons.size(); ++p) {
      const auto same = [](const Ring& r, const Ring& s) {
        if (r.size() != s.size()) return false;
        for (size_t k = 0; k < r.size(); ++k)
          if (!SamePoint(r[k], s[k])) return false;
        return true;
      };
      EXPECT_TRUE(same(f.polygons[p].shell, g.polygons[p].shell)) << "feature " << i;
      ASSERT_EQ(f.polygons[p].holes.size(), g.polygons[p].holes.size());
      for (size_t h = 0; h < f.polygons[p].holes.size(); ++h)
        EXPECT_TRUE(same(f.polygons[p].holes[h], g.polygons[p].holes[h])) << "feature " << i;
    }
    ASSERT_EQ(f.lines.size(), g.lines.size());
    for (size_t l = 0; l < f.lines.size(); ++l) {
      ASSERT_EQ(f.lines[l].size(), g.lines[l].size());
      for (size_t k = 0; k < f.lines[l].size(); ++k)
        EXPECT_TRUE(SamePoint(f.lines[l][k], g.lines[l][k]));
    }
  }
}

TEST(LandXmlWriterTest, ReadsBackBitForBit) {
  TempDir dir;
  const LandXmlSurface s = SampleSurface();
  const std::string path = dir.Path("s.xml");
  ASSERT_TRUE(WriteLandXml(s, path).ok());
  auto back = ReadLandXml(path);
  ASSERT_TRUE(back.ok()) << back.status().message();
  ExpectSame(s, *back);
}

// libxml2's XPath over the written file: a reader we did not write sees LandXML's structure.
class XPathDoc {
 public:
  explicit XPathDoc(const std::string& path)
      : doc_(xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_HUGE)) {
    if (doc_ == nullptr) return;
    ctx_ = xmlXPathNewContext(doc_);
    xmlXPathRegisterNs(ctx_, BAD_CAST "l", BAD_CAST kLandXmlNamespace);
    xmlXPathRegisterNs(ctx_, BAD_CAST "tb", BAD_CAST kTinbaseLandXmlNamespace);
  }
  ~XPathDoc() {
    if (ctx_ != nullptr) xmlXPathFreeContext(ctx_);
    if (doc_ != nullptr) xmlFreeDoc(doc_);
  }
  bool ok() const { return doc_ != nullptr; }
  double Number(const std::string& expr) const {
    xmlXPathObjectPtr r = xmlXPathEvalExpression(BAD_CAST expr.c_str(), ctx_);
    EXPECT_NE(r, nullptr) << expr;
    if (r == nullptr) return NAN;
    const double v = xmlXPathCastToNumber(r);
    xmlXPathFreeObject(r);
    return v;
  }
  std::string String(const std::string& expr) const {
    xmlXPathObjectPtr r = xmlXPathEvalExpression(BAD_CAST expr.c_str(), ctx_);
    EXPECT_NE(r, nullptr) << expr;
    if (r == nullptr) return "";
    xmlChar* s = xmlXPathCastToString(r);
    std::string out(reinterpret_cast<const char*>(s));
    xmlFree(s);
    xmlXPathFreeObject(r);
    return out;
  }

 private:
  xmlDocPtr doc_ = nullptr;
  xmlXPathContextPtr ctx_ = nullptr;
};

TEST(LandXmlWriterTest, Libxml2SeesLandXmlStructure) {
  TempDir dir;
  const LandXmlSurface s = SampleSurface();
  const std::string path = dir.Path("s.xml");
  ASSERT_TRUE(WriteLandXml(s, path).ok());
  XPathDoc doc(path);
  ASSERT_TRUE(doc.ok());
  EXPECT_EQ(doc.String("/l:LandXML/@version"), "1.2");
  EXPECT_EQ(doc.String("/l:LandXML/l:Units/l:Metric/@linearUnit"), "meter");
  EXPECT_EQ(doc.String("/l:LandXML/l:CoordinateSystem/@epsgCode"), "32632");
  EXPECT_EQ(doc.String("/l:LandXML/l:CoordinateSystem/@ogcWktCode"), s.crs_wkt);
  const std::string surface = "/l:LandXML/l:Surfaces/l:Surface";
  EXPECT_EQ(doc.String(surface + "/@name"), s.name);
  EXPECT_EQ(doc.String(surface + "/l:Definition/@surfType"), "TIN");
  const std::string def = surface + "/l:Definition";
  EXPECT_EQ(doc.Number("count(" + def + "/l:Pnts/l:P)"), s.tin.vertices.size());
  EXPECT_EQ(doc.Number("count(" + def + "/l:Faces/l:F)"), s.tin.triangles.size());
  size_t hidden = 0, boundary_edges = 0;
  for (const TinTriangle& t : s.tin.triangles) {
    hidden += !t.visible;
    for (int32_t n : t.n) boundary_edges += n == kNoNeighbour;
  }
  EXPECT_EQ(doc.Number("count(" + def + "/l:Faces/l:F[@i='1'])"), hidden);
  EXPECT_EQ(doc.Number("count(" + def + "/l:Faces/l:F[not(@i)])"), s.tin.triangles.size() - hidden);
  EXPECT_EQ(doc.Number("count(" + def + "/l:Faces/l:F[@n])"), s.tin.triangles.size());
  // P: "northing easting elevation", parsed by XPath's own number().
  const TinVertex& v7 = s.tin.vertices[6];
  const std::string p7 = doc.String(def + "/l:Pnts/l:P[@id='7']");
  std::istringstream in(p7);
  double y = 0, x = 0, z = 0;
  in >> y >> x >> z;
  EXPECT_EQ(y, v7.y) << p7;
  EXPECT_EQ(x, v7.x) << p7;
  EXPECT_EQ(z, v7.z) << p7;
  // F: point ids 1-based; n[k] is the face across (p_k, p_k+1), 1-based, 0 on the boundary.
  const TinTriangle& t = s.tin.triangles[30];
  const std::string f = def + "/l:Faces/l:F[31]";
  EXPECT_EQ(doc.String(f), std::to_string(t.v[0] + 1) + " " + std::to_string(t.v[1] + 1) + " " +
                               std::to_string(t.v[2] + 1));
  const auto n1 = [](int32_t n) { return std::to_string(n == kNoNeighbour ? 0 : n + 1); };
  EXPECT_EQ(doc.String(f + "/@n"), n1(t.n[2]) + " " + n1(t.n[0]) + " " + n1(t.n[1]));
  // Each zero in n is a boundary edge.
  double zeros = 0;
  for (size_t k = 1; k <= s.tin.triangles.size(); ++k) {
    std::istringstream ns(doc.String(def + "/l:Faces/l:F[" + std::to_string(k) + "]/@n"));
    for (int a = 0, j = 0; j < 3 && ns >> a; ++j) zeros += a == 0;
  }
  EXPECT_EQ(zeros, boundary_edges);
  // The features' rings: the fill's shell and hole and the fault as breaklines, the clip's
  // shell as the outer boundary; closed rings repeat their first point.
  const std::string src = surface + "/l:SourceData";
  EXPECT_EQ(doc.Number("count(" + src + "/l:Breaklines/l:Breakline)"), 3);
  EXPECT_EQ(doc.Number("count(" + src + "/l:Boundaries/l:Boundary[@bndType='outer'])"), 1);
  std::istringstream ring(doc.String(src + "/l:Boundaries/l:Boundary/l:PntList2D"));
  std::vector<double> values;
  for (double v = 0; ring >> v;) values.push_back(v);
  ASSERT_EQ(values.size(), 10u);
  EXPECT_EQ(values[0], s.features[1].polygons[0].shell[0].y);
  EXPECT_EQ(values[1], s.features[1].polygons[0].shell[0].x);
  EXPECT_EQ(values[8], values[0]);
  EXPECT_EQ(values[9], values[1]);
  EXPECT_EQ(
      doc.Number("count(" + surface + "/l:Feature[@code='tinbase']/l:Property[@label='tag'])"), 2);
  EXPECT_EQ(doc.Number("count(//l:Feature[@code='tinbase:feature'])"), 3);
  EXPECT_EQ(doc.Number("count(//l:Feature[@code='tinbase:constraints']/l:Property)"), 5);
}

TEST(LandXmlWriterTest, UnitsFollowTheLinearUnit) {
  EXPECT_STREQ(UnitsFor(1.0).linear, "meter");
  EXPECT_STREQ(UnitsFor(0.3048).system, "Imperial");
  EXPECT_STREQ(UnitsFor(0.3048).linear, "foot");
  EXPECT_STREQ(UnitsFor(1200.0 / 3937.0).linear, "USSurveyFoot");
  TempDir dir;
  LandXmlSurface s = SampleSurface();
  s.metres_per_unit = 1200.0 / 3937.0;
  ASSERT_TRUE(WriteLandXml(s, dir.Path("ft.xml")).ok());
  XPathDoc doc(dir.Path("ft.xml"));
  ASSERT_TRUE(doc.ok());
  EXPECT_EQ(doc.String("/l:LandXML/l:Units/l:Imperial/@linearUnit"), "USSurveyFoot");
  auto back = ReadLandXml(dir.Path("ft.xml"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->metres_per_unit, 1200.0 / 3937.0);
}

TEST(LandXmlWriterTest, UnwritablePathIsAnIOError) {
  const Status s = WriteLandXml(SampleSurface(), "/nonexistent-dir/s.xml");
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("/nonexistent-dir/s.xml"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace tinbase
