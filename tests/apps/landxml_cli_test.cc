// `tinbase export --format landxml`, `tinbase import landxml` and `tinbase export --format vdb`
// end to end on real data (the Hamersley DEM, its geology as fill polygons, its faults as
// breaklines, an erase polygon with a hole): the LandXML goes out and back into a surface equal
// triangle for triangle (coordinates bit for bit, neighbours, visibility, tags, features,
// constraint owners) that passes `check --full`; libxml2's XPath and OpenVDB's vdb_print read
// the files; bad input is rejected with one line naming the place, changing no store and
// leaving no output file.
#include <gtest/gtest.h>
#include <libxml/parser.h>
#include <libxml/xpath.h>
#include <libxml/xpathInternals.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "db/export/landxml_export.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TableChecksums;
using testing::TempDir;

using Xyz = std::tuple<double, double, double>;

// A surface in a form that does not depend on store ids or row order: each triangle as its
// corners rotated to start at the smallest, with its paint and the triangles across its edges
// (by their own rotated corners), sorted.
struct CanonicalTriangle {
  std::array<Xyz, 3> corners;
  bool visible = true;
  std::string tag;
  std::array<std::array<Xyz, 3>, 3> across{};  // across the edge opposite corners[i]
  bool operator<(const CanonicalTriangle& o) const { return corners < o.corners; }
  bool operator==(const CanonicalTriangle& o) const {
    return corners == o.corners && visible == o.visible && tag == o.tag && across == o.across;
  }
};

struct Canonical {
  std::vector<std::tuple<double, double, double, int>> vertices;
  std::vector<CanonicalTriangle> triangles;
  std::vector<std::tuple<Xyz, Xyz, std::string>> constraints;  // by owner's position
  // mode, tag, attributes, polygons, lines (names of untagged features hold store ids)
  std::vector<std::tuple<std::string, std::string, std::string, size_t, size_t>> features;
};

Canonical CanonicalOf(const LandXmlSurface& s) {
  Canonical c;
  const Tin& tin = s.tin;
  const auto xyz = [&](uint32_t v) {
    return Xyz{tin.vertices[v].x, tin.vertices[v].y, tin.vertices[v].z};
  };
  for (const TinVertex& v : tin.vertices)
    c.vertices.emplace_back(v.x, v.y, v.z, static_cast<int>(v.kind));
  std::sort(c.vertices.begin(), c.vertices.end());
  // Rotation of each triangle that starts at its smallest corner.
  std::vector<int> start(tin.triangles.size());
  std::vector<std::array<Xyz, 3>> corners(tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const auto& v = tin.triangles[t].v;
    int s0 = 0;
    for (int k = 1; k < 3; ++k)
      if (xyz(v[k]) < xyz(v[s0])) s0 = k;
    start[t] = s0;
    for (int k = 0; k < 3; ++k) corners[t][k] = xyz(v[(s0 + k) % 3]);
  }
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    const TinTriangle& tri = tin.triangles[t];
    CanonicalTriangle ct;
    ct.corners = corners[t];
    ct.visible = tri.visible;
    ct.tag = tri.tag == kNoTag ? "" : tin.tags[tri.tag];
    for (int k = 0; k < 3; ++k) {
      const int32_t n = tri.n[(start[t] + k) % 3];
      if (n != kNoNeighbour) ct.across[k] = corners[n];
    }
    c.triangles.push_back(ct);
  }
  std::sort(c.triangles.begin(), c.triangles.end());
  for (const LandXmlConstraint& k : s.constraints) {
    Xyz a = xyz(k.a), b = xyz(k.b);
    if (b < a) std::swap(a, b);
    c.constraints.emplace_back(a, b, k.feature ? std::to_string(*k.feature) : "");
  }
  std::sort(c.constraints.begin(), c.constraints.end());
  for (const LandXmlFeature& f : s.features)
    c.features.emplace_back(FeatureModeName(f.mode), f.tag.value_or(""), f.attributes,
                            f.polygons.size(), f.lines.size());
  return c;
}

Canonical Stored(const std::string& store_path, const std::string& name) {
  auto store = Store::Open(store_path, Store::Access::kReadOnly);
  EXPECT_TRUE(store.ok()) << store.status().message();
  SurfaceStore surfaces(**store);
  auto info = surfaces.Find(name);
  EXPECT_TRUE(info.ok()) << info.status().message();
  auto s = LoadLandXmlSurface(**store, *info);
  EXPECT_TRUE(s.ok()) << s.status().message();
  return CanonicalOf(*s);
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void Spit(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The files left in `dir` whose names contain `part` (e.g. ".partial").
int FilesWith(const std::string& dir, const std::string& part) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    n += e.path().filename().string().find(part) != std::string::npos;
  return n;
}

double XPathNumber(const std::string& path, const std::string& expr) {
  xmlDocPtr doc = xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_HUGE);
  if (doc == nullptr) return -1;
  xmlXPathContextPtr ctx = xmlXPathNewContext(doc);
  xmlXPathRegisterNs(ctx, BAD_CAST "l", BAD_CAST kLandXmlNamespace);
  xmlXPathObjectPtr r = xmlXPathEvalExpression(BAD_CAST expr.c_str(), ctx);
  const double v = r != nullptr ? xmlXPathCastToNumber(r) : -1;
  if (r != nullptr) xmlXPathFreeObject(r);
  xmlXPathFreeContext(ctx);
  xmlFreeDoc(doc);
  return v;
}

// The string value of XPath `expr` in the file (libxml2's own reader), "" when it cannot be read.
std::string XPathString(const std::string& path, const std::string& expr) {
  xmlDocPtr doc = xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_HUGE);
  if (doc == nullptr) return "";
  xmlXPathContextPtr ctx = xmlXPathNewContext(doc);
  xmlXPathRegisterNs(ctx, BAD_CAST "l", BAD_CAST kLandXmlNamespace);
  xmlXPathObjectPtr r = xmlXPathEvalExpression(BAD_CAST expr.c_str(), ctx);
  std::string v;
  if (r != nullptr) {
    xmlChar* text = xmlXPathCastToString(r);
    v = reinterpret_cast<const char*>(text);
    xmlFree(text);
    xmlXPathFreeObject(r);
  }
  xmlXPathFreeContext(ctx);
  xmlFreeDoc(doc);
  return v;
}

nlohmann::json SurfaceInfoJson(const std::string& store, const std::string& name) {
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store)));
  for (const auto& s : info["surfaces"])
    if (s["name"] == name) return s;
  ADD_FAILURE() << "no surface " << name;
  return {};
}

// The store is made once per ctest run (a DEM, a TIN, 97 features: a few seconds) and each
// test works on its own copy.
class LandXmlCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(Recipe(), store_);
    xml_ = dir_.Path("t.xml");
    RunWrite(store_, "export " + Quote(store_) + " --surface t --format landxml -o " + Quote(xml_));
  }
  static const testing::StoreRecipe& Recipe() {
    static const testing::StoreRecipe recipe{
        "landxml_cli_test", [](const std::string& store, const TempDir& scratch) {
          testing::MakeDemStore(store, "geology/hamersley/dtm_rp.tif");
          RunWrite(store,
                   "tin build " + Quote(store) + " --surface t --method greedy --tolerance 20");
          RunWrite(store, "polygon add " + Quote(store) + " " +
                              Quote(DataPath("geology/hamersley/geology.geojson")) +
                              " --surface t --mode fill --tag-field unitname");
          RunWrite(store, "polygon add " + Quote(store) + " " +
                              Quote(DataPath("geology/hamersley/faults.geojson")) +
                              " --surface t --mode breakline");
          const std::string pit = testing::WritePolygons(scratch, "pit.geojson",
                                                         {{{{530000, 7490000},
                                                            {540000, 7490000},
                                                            {540000, 7500000},
                                                            {530000, 7500000},
                                                            {530000, 7490000}},
                                                           {{533000, 7493000},
                                                            {533000, 7496000},
                                                            {536000, 7496000},
                                                            {536000, 7493000},
                                                            {533000, 7493000}}}});
          RunWrite(store,
                   "polygon add " + Quote(store) + " " + Quote(pit) + " --surface t --mode erase");
        }};
    return recipe;
  }
  static std::string Dem() { return DataPath("geology/hamersley/dtm_rp.tif"); }
  TempDir dir_;
  std::string store_;
  std::string xml_;
};

TEST_F(LandXmlCliTest, RoundTripGivesAnIdenticalCheckedSurface) {
  const nlohmann::json t = SurfaceInfoJson(store_, "t");
  // libxml2 sees every point and face, and the hidden ones marked.
  const std::string def = "/l:LandXML/l:Surfaces/l:Surface/l:Definition";
  EXPECT_EQ(XPathNumber(xml_, "count(" + def + "/l:Pnts/l:P)"), t["vertices"].get<double>());
  EXPECT_EQ(XPathNumber(xml_, "count(" + def + "/l:Faces/l:F)"), t["triangles"].get<double>());
  EXPECT_EQ(XPathNumber(xml_, "count(" + def + "/l:Faces/l:F[@i='1'])"),
            t["triangles"].get<double>() - t["visible_triangles"].get<double>());
  EXPECT_GT(XPathNumber(xml_, "count(//l:SourceData/l:Breaklines/l:Breakline)"), 35);
  EXPECT_EQ(XPathNumber(xml_, "count(//l:SourceData/l:Boundaries/l:Boundary)"), 2);

  const nlohmann::json report = Json(RunWrite(
      store_, "import landxml " + Quote(store_) + " " + Quote(xml_) + " --surface t2 --json"));
  EXPECT_EQ(report["surface"], "t2");
  EXPECT_EQ(report["kind"], "delaunay");
  EXPECT_EQ(report["features"], 97);
  const nlohmann::json t2 = SurfaceInfoJson(store_, "t2");
  for (const char* key : {"vertices", "triangles", "visible_triangles", "constraints", "features"})
    EXPECT_EQ(t2[key], t[key]) << key;
  const Canonical a = Stored(store_, "t"), b = Stored(store_, "t2");
  EXPECT_EQ(a.vertices, b.vertices);
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (size_t i = 0; i < a.triangles.size(); ++i)
    ASSERT_TRUE(a.triangles[i] == b.triangles[i]) << "triangle " << i << " differs";
  EXPECT_TRUE(a.constraints == b.constraints) << "constraint rows or owners differ";
  EXPECT_TRUE(a.features == b.features) << "features differ";

  // A selection holds the selected triangles alone, without features.
  const std::string visible = dir_.Path("visible.xml");
  RunWrite(store_, "export " + Quote(store_) + " --surface t --visible-only --format landxml -o " +
                       Quote(visible));
  EXPECT_EQ(XPathNumber(visible, "count(" + def + "/l:Faces/l:F)"),
            t["visible_triangles"].get<double>());
  EXPECT_EQ(XPathNumber(visible, "count(" + def + "/l:Faces/l:F[@i='1'])"), 0);
  EXPECT_EQ(XPathNumber(visible, "count(//l:SourceData)"), 0);
}

// Another program's TIN: arbitrary point ids, clockwise faces, no neighbours, no CRS, no tinbase
// attributes. It becomes a `free` surface that passes the full check.
TEST(LandXmlForeignCliTest, ImportsAnotherProgramsTin) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase"), xml = dir.Path("foreign.xml");
  RunWrite(store, "init " + Quote(store));
  std::ostringstream text;
  text << "<?xml version=\"1.0\"?>\n<LandXML xmlns=\"http://www.landxml.org/schema/LandXML-1.2\" "
          "version=\"1.2\" date=\"2026-01-01\" time=\"00:00:00\">\n"
          "<Surfaces><Surface name=\"EG\"><Definition surfType=\"TIN\"><Pnts>\n";
  // A 3 x 3 grid of points with ids 101.., z a tilted plane.
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      text << "<P id=\"" << 101 + 3 * j + i << "\">" << 5000 + 10 * j << " " << 2000 + 10 * i << " "
           << 100 + i + 2 * j << "</P>\n";
  text << "</Pnts><Faces>\n";
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const int a = 101 + 3 * j + i, b = a + 1, c = a + 4, d = a + 3;
      text << "<F>" << a << " " << c << " " << b << "</F>\n";  // clockwise
      text << "<F>" << a << " " << d << " " << c << "</F>\n";
    }
  }
  text << "</Faces></Definition></Surface></Surfaces></LandXML>\n";
  Spit(xml, text.str());
  const nlohmann::json r =
      Json(RunWrite(store, "import landxml " + Quote(store) + " " + Quote(xml) + " --json"));
  EXPECT_EQ(r["surface"], "EG");
  EXPECT_EQ(r["kind"], "free");
  EXPECT_EQ(r["vertices"], 9);
  EXPECT_EQ(r["triangles"], 8);
  EXPECT_EQ(r["features"], 0);
}

TEST_F(LandXmlCliTest, ImportIntoAnotherStoreNeedsTheDemThatHidTriangles) {
  const std::string other = StoreTarget(dir_, "other.tinbase");
  RunWrite(other, "init " + Quote(other));
  // Two triangles of t are hidden by DEM nodata alone: without the DEM they have no reason.
  ExpectRejected(other, "import landxml " + Quote(other) + " " + Quote(xml_),
                 "draped on DEM 'dtm_rp'");
  RunWrite(other, "dem import " + Quote(other) + " " + Quote(Dem()));
  RunWrite(other, "import landxml " + Quote(other) + " " + Quote(xml_));
  EXPECT_EQ(Json(RunCli("info --json " + Quote(other)))["crs"], "EPSG:28350");
  const Canonical a = Stored(store_, "t"), b = Stored(other, "t");
  EXPECT_TRUE(a.triangles == b.triangles);
  EXPECT_TRUE(a.constraints == b.constraints);
}

TEST_F(LandXmlCliTest, BadLandXmlIsRejectedNamingTheLineAndChangesNothing) {
  const std::string text = Slurp(xml_);
  const std::string import = "import landxml " + Quote(store_) + " ";
  // The name is taken.
  ExpectRejected(store_, import + Quote(xml_), "surface 't' already exists");
  ExpectRejected(store_, import + Quote(xml_) + " --surface u --dem nosuch", "nosuch");
  // Not XML at all.
  const std::string junk = dir_.Path("junk.xml");
  Spit(junk, "surface,x,y\n1,2,3\n");
  ExpectRejected(store_, import + Quote(junk), "line 1: not well-formed XML");
  // No Surface/Definition.
  const std::string empty = dir_.Path("empty.xml");
  Spit(empty, text.substr(0, text.find("<Surfaces>")) + "</LandXML>\n");
  ExpectRejected(store_, import + Quote(empty), "no Surfaces/Surface/Definition");
  // A face naming a point that is not there, and a coordinate that is not a number: the
  // message names the element and its line.
  const auto line_of = [&](size_t at) {
    return std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n'));
  };
  std::string bad_face = text;
  const size_t f = bad_face.find("<F ");
  const size_t f_text = bad_face.find('>', f) + 1;
  bad_face.replace(f_text, bad_face.find(' ', f_text) - f_text, "99999999");
  Spit(dir_.Path("face.xml"), bad_face);
  ExpectRejected(store_, import + Quote(dir_.Path("face.xml")) + " --surface u",
                 "line " + line_of(f) + ", <F>: face refers to point 99999999");
  std::string bad_point = text;
  const size_t p = bad_point.find("<P ", bad_point.find("<Pnts>") + 1000);
  const size_t p_text = bad_point.find('>', p) + 1;
  bad_point.replace(p_text, bad_point.find(' ', p_text) - p_text, "12x");
  Spit(dir_.Path("point.xml"), bad_point);
  ExpectRejected(store_, import + Quote(dir_.Path("point.xml")) + " --surface u",
                 "line " + line_of(p) + ", <P>: '12x' is not a number");
  // Another CRS than the store's.
  std::string wgs84 = text;
  const size_t cs = wgs84.find("<CoordinateSystem");
  wgs84.replace(cs, wgs84.find("/>", cs) + 2 - cs,
                "<CoordinateSystem epsgCode=\"4326\" ogcWktCode=\"GEOGCS[&quot;WGS 84&quot;,"
                "DATUM[&quot;WGS_1984&quot;,SPHEROID[&quot;WGS 84&quot;,6378137,298.257223563]],"
                "PRIMEM[&quot;Greenwich&quot;,0],UNIT[&quot;degree&quot;,0.0174532925199433]]\"/>");
  Spit(dir_.Path("wgs84.xml"), wgs84);
  ExpectRejected(store_, import + Quote(dir_.Path("wgs84.xml")) + " --surface u",
                 "CoordinateSystem: the file is in");
  // A hidden face with no feature to hide it fails the integrity check inside the import.
  std::string shown = text;
  const size_t hidden = shown.find(" i=\"1\"");
  ASSERT_NE(hidden, std::string::npos);
  shown.erase(hidden, 6);
  Spit(dir_.Path("shown.xml"), shown);
  ExpectRejected(store_, import + Quote(dir_.Path("shown.xml")) + " --surface u",
                 "does not pass the integrity check (wrong-visibility)");
}

TEST_F(LandXmlCliTest, BadExportsLeaveNoFile) {
  const std::string out = dir_.Path("out");
  std::filesystem::create_directory(out);
  const std::string exp = "export " + Quote(store_) + " --surface ";
  ExpectRejected(store_, exp + "nosuch --format landxml -o " + Quote(out + "/a.xml"),
                 "no surface named 'nosuch'");
  ExpectRejected(store_, exp + "t --format landxml -o /nonexistent-dir/a.xml", "/nonexistent-dir");
  ExpectRejected(store_, exp + "t --format vdb --voxel -1 -o " + Quote(out + "/a.vdb"),
                 "not a positive number");
  ExpectRejected(store_, exp + "t --format vdb --voxel 0.5 -o " + Quote(out + "/a.vdb"),
                 "give a larger --voxel");
  ExpectRejected(store_, exp + "t --format vdb --floor 5000 -o " + Quote(out + "/a.vdb"),
                 "must lie below");
  EXPECT_EQ(FilesWith(out, ""), 0) << "a rejected export left a file";
}

// A 3D line (--z-from feature) goes out as a PntList3D of its own z, and comes back in as a 3D
// line with the same z, on an identical surface.
TEST_F(LandXmlCliTest, ThreeDLinesKeepTheirZThroughLandXml) {
  const std::vector<std::array<double, 2>> plan = {
      {545000.25, 7505000.5}, {547000.75, 7506500.25}, {549500.5, 7507000.75}};
  std::vector<double> z;
  for (const auto& [x, y] : plan) {
    const nlohmann::json sample = Json(RunCli("dem sample --json " + Quote(store_) + " -- " +
                                              std::to_string(x) + " " + std::to_string(y)));
    z.push_back((sample.is_array() ? sample[0]["z"] : sample["z"]).get<double>() + 2.5);
  }
  const std::string line = dir_.Path("ridge.geojson");
  {
    std::ofstream out(line);
    out.precision(17);
    out << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": {"name": )"
        << R"("urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": "Feature", "properties": )"
        << R"({}, "geometry": {"type": "LineString", "coordinates": [)";
    for (size_t i = 0; i < plan.size(); ++i)
      out << (i ? "," : "") << "[" << plan[i][0] << "," << plan[i][1] << "," << z[i] << "]";
    out << "]}}]}\n";
  }
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(line) +
                       " --surface t --mode breakline --z-from feature --tag ridge");
  const std::string xml = dir_.Path("ridge.xml");
  RunWrite(store_, "export " + Quote(store_) + " --surface t --format landxml -o " + Quote(xml));

  // libxml2 reads the line's own z: y x z triples, as LandXML orders them.
  EXPECT_EQ(XPathNumber(xml, "count(//l:Breaklines/l:Breakline/l:PntList3D)"), 1);
  std::ostringstream expected;
  expected.precision(17);
  for (size_t i = 0; i < plan.size(); ++i)
    expected << (i ? " " : "") << plan[i][1] << " " << plan[i][0] << " " << z[i];
  const std::string text = XPathString(xml, "string(//l:Breaklines/l:Breakline/l:PntList3D)");
  std::istringstream got(text), want(expected.str());
  double a = 0, b = 0;
  int numbers = 0;
  while (want >> b) {
    ASSERT_TRUE(static_cast<bool>(got >> a)) << text;
    EXPECT_EQ(a, b) << text;
    ++numbers;
  }
  EXPECT_EQ(numbers, 9);

  RunWrite(store_, "import landxml " + Quote(store_) + " " + Quote(xml) + " --surface t3");
  const Canonical before = Stored(store_, "t"), after = Stored(store_, "t3");
  EXPECT_EQ(before.vertices, after.vertices);
  EXPECT_TRUE(before.triangles == after.triangles);
  EXPECT_TRUE(before.features == after.features);
  auto opened = Store::Open(store_, Store::Access::kReadOnly);
  ASSERT_TRUE(opened.ok()) << opened.status().ToString();
  auto surface = SurfaceStore(**opened).Find("t3");
  ASSERT_TRUE(surface.ok()) << surface.status().ToString();
  auto read = LoadLandXmlSurface(**opened, *surface);
  ASSERT_TRUE(read.ok()) << read.status().ToString();
  int three_d = 0;
  for (const LandXmlFeature& f : read->features) {
    if (f.z_from != ZFrom::kFeature) continue;
    ++three_d;
    EXPECT_EQ(f.tag, "ridge");
    ASSERT_EQ(f.line_z.size(), 1u);
    EXPECT_EQ(f.line_z[0], z) << "the imported line keeps the file's z";
  }
  EXPECT_EQ(three_d, 1);

  // A 3D line without its z in the file is refused, naming the element.
  std::string flat = Slurp(xml);
  const size_t list = flat.find("<PntList3D>");
  ASSERT_NE(list, std::string::npos);
  const size_t end = flat.find("</PntList3D>", list);
  std::ostringstream pairs;
  pairs.precision(17);
  for (size_t i = 0; i < plan.size(); ++i)
    pairs << (i ? " " : "") << plan[i][1] << " " << plan[i][0];
  flat.replace(list, end + 12 - list, "<PntList2D>" + pairs.str() + "</PntList2D>");
  Spit(dir_.Path("flat.xml"), flat);
  ExpectRejected(
      store_,
      "import landxml " + Quote(store_) + " " + Quote(dir_.Path("flat.xml")) + " --surface t4",
      "needs its z (a PntList3D)");
}

TEST_F(LandXmlCliTest, VdbExportsReadByVdbPrint) {
  RunWrite(store_, "tin build " + Quote(store_) + " --surface coarse --method rtin --tolerance 60");
  const std::string level_set = dir_.Path("t.vdb"), fog = dir_.Path("th.vdb");
  CliResult r = RunCli("export " + Quote(store_) + " --surface t --format vdb --voxel 400 -o " +
                       Quote(level_set));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("level set"), std::string::npos) << r.out;
  r = RunCli("export " + Quote(store_) + " --surface coarse --base t --format vdb --voxel 300 -o " +
             Quote(fog));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fog volume"), std::string::npos) << r.out;
  for (const auto& [path, cls] :
       {std::pair{level_set, "class: level set"}, std::pair{fog, "class: fog volume"}}) {
    const int has_tool = std::system("command -v vdb_print > /dev/null 2>&1");
    ASSERT_EQ(has_tool, 0) << "vdb_print is not installed (Debian package libopenvdb-tools)";
    const std::string listing = dir_.Path("listing.txt");
    ASSERT_EQ(
        std::system(("vdb_print -l " + Quote(path) + " > " + Quote(listing) + " 2>&1").c_str()), 0)
        << Slurp(listing);
    EXPECT_NE(Slurp(listing).find(cls), std::string::npos) << Slurp(listing);
    EXPECT_NE(Slurp(listing).find("tinbase:crs"), std::string::npos) << Slurp(listing);
  }
}

}  // namespace
}  // namespace tinbase
