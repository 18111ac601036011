#include "core/export/landxml_writer.h"

#include <libxml/xmlwriter.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <ctime>
#include <memory>

namespace tinbase {

namespace {

// Appends the shortest text that reads back as exactly `v` (std::to_chars' guarantee).
void AppendNumber(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

std::string Number(double v) {
  std::string s;
  AppendNumber(s, v);
  return s;
}

// "y x y x ...": a ring or line as LandXML's PntList2D (northing first), closed rings repeating
// their first point as LandXML closes them.
std::string PointList2D(const std::vector<Point2>& points, bool close) {
  std::string s;
  auto add = [&](const Point2& p) {
    if (!s.empty()) s += ' ';
    AppendNumber(s, p.y);
    s += ' ';
    AppendNumber(s, p.x);
  };
  for (const Point2& p : points) add(p);
  if (close && !points.empty()) add(points.front());
  return s;
}

// "y x z y x z ...": a 3D line as LandXML's PntList3D (northing, easting, elevation), `z[i]` the
// elevation of points[i].
std::string PointList3D(const std::vector<Point2>& points, const std::vector<double>& z) {
  std::string s;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!s.empty()) s += ' ';
    AppendNumber(s, points[i].y);
    s += ' ';
    AppendNumber(s, points[i].x);
    s += ' ';
    AppendNumber(s, z[i]);
  }
  return s;
}

struct WriterDeleter {
  void operator()(xmlTextWriter* w) const { xmlFreeTextWriter(w); }
};

// xmlTextWriter calls that remember the first failure, so the writing code reads as the
// document's structure and the error is checked once at the end.
class XmlOut {
 public:
  explicit XmlOut(xmlTextWriter* w) : w_(w) {}
  XmlOut& Start(const char* name) {
    Check(xmlTextWriterStartElement(w_, Cast(name)));
    return *this;
  }
  XmlOut& Attr(const char* name, const std::string& value) {
    Check(xmlTextWriterWriteAttribute(w_, Cast(name), Cast(value.c_str())));
    return *this;
  }
  XmlOut& Text(const std::string& text) {
    Check(xmlTextWriterWriteString(w_, Cast(text.c_str())));
    return *this;
  }
  XmlOut& End() {
    Check(xmlTextWriterEndElement(w_));
    return *this;
  }
  // <name label=".." value=".."/>, LandXML's Property.
  XmlOut& Property(const std::string& label, const std::string& value) {
    return Start("Property").Attr("label", label).Attr("value", value).End();
  }
  void Check(int rc) { ok_ = ok_ && rc >= 0; }
  bool ok() const { return ok_; }

 private:
  static const xmlChar* Cast(const char* s) { return reinterpret_cast<const xmlChar*>(s); }
  xmlTextWriter* w_;
  bool ok_ = true;
};

std::string Today(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, format, &utc);
  return buf;
}

void WriteUnits(XmlOut& out, double metres_per_unit) {
  const LandXmlUnits units = UnitsFor(metres_per_unit);
  const bool metric = std::string(units.system) == "Metric";
  out.Start("Units").Start(units.system);
  out.Attr("areaUnit", metric ? "squareMeter" : "squareFoot");
  out.Attr("linearUnit", units.linear);
  out.Attr("volumeUnit", metric ? "cubicMeter" : "cubicFeet");
  out.Attr("temperatureUnit", metric ? "celsius" : "fahrenheit");
  out.Attr("pressureUnit", metric ? "milliBars" : "inHG");
  out.Attr("angularUnit", "decimal degrees").Attr("directionUnit", "decimal degrees");
  out.End().End();
}

void WriteCoordinateSystem(XmlOut& out, const LandXmlSurface& s) {
  if (s.crs_wkt.empty()) return;
  out.Start("CoordinateSystem");
  if (!s.crs_name.empty()) out.Attr("name", s.crs_name);
  if (s.epsg) out.Attr("epsgCode", std::to_string(*s.epsg));
  out.Attr("ogcWktCode", s.crs_wkt).End();
}

// The tinbase attributes naming a ring: feature (1-based), polygon and ring (0-based; ring 0 is
// the shell).
void RingAttrs(XmlOut& out, size_t feature, size_t polygon, size_t ring) {
  out.Attr("tb:feature", std::to_string(feature + 1));
  out.Attr("tb:polygon", std::to_string(polygon));
  out.Attr("tb:ring", std::to_string(ring));
}

// LandXML's boundary type of a ring: a clip polygon's shell is the surface's outer boundary and
// its holes are voids; an erase polygon's shell is a void and its holes islands in it.
const char* BoundaryType(FeatureMode mode, size_t ring) {
  if (mode == FeatureMode::kClip) return ring == 0 ? "outer" : "void";
  return ring == 0 ? "void" : "island";
}

// LandXML's breakline type of a line feature. Readers take a standard breakline for a slope
// break; a softline is an edge for shape only, on the surface's own elevations, which is what
// LandXML's nondestructive breakline is (it changes no elevation of the surface it crosses).
const char* BreaklineType(FeatureMode mode) {
  return mode == FeatureMode::kSoftline ? "nondestructive" : "standard";
}

bool IsBoundary(FeatureMode mode) {
  return mode == FeatureMode::kClip || mode == FeatureMode::kErase;
}

void WriteSourceData(XmlOut& out, const LandXmlSurface& s) {
  bool breaklines = false, boundaries = false;
  for (const LandXmlFeature& f : s.features) (IsBoundary(f.mode) ? boundaries : breaklines) = true;
  if (!breaklines && !boundaries) return;
  out.Start("SourceData");
  if (breaklines) {
    out.Start("Breaklines");
    for (size_t i = 0; i < s.features.size(); ++i) {
      const LandXmlFeature& f = s.features[i];
      if (IsBoundary(f.mode)) continue;
      for (size_t l = 0; l < f.lines.size(); ++l) {
        out.Start("Breakline").Attr("brkType", BreaklineType(f.mode)).Attr("name", f.name);
        RingAttrs(out, i, l, 0);
        if (f.z_from == ZFrom::kFeature && l < f.line_z.size() &&
            f.line_z[l].size() == f.lines[l].size()) {
          out.Start("PntList3D").Text(PointList3D(f.lines[l], f.line_z[l])).End().End();
        } else {
          out.Start("PntList2D").Text(PointList2D(f.lines[l], false)).End().End();
        }
      }
      for (size_t p = 0; p < f.polygons.size(); ++p) {
        const Polygon& polygon = f.polygons[p];
        for (size_t r = 0; r <= polygon.holes.size(); ++r) {
          out.Start("Breakline").Attr("brkType", "standard").Attr("name", f.name);
          RingAttrs(out, i, p, r);
          const Ring& ring = r == 0 ? polygon.shell : polygon.holes[r - 1];
          out.Start("PntList2D").Text(PointList2D(ring, true)).End().End();
        }
      }
    }
    out.End();
  }
  if (boundaries) {
    out.Start("Boundaries");
    for (size_t i = 0; i < s.features.size(); ++i) {
      const LandXmlFeature& f = s.features[i];
      if (!IsBoundary(f.mode)) continue;
      for (size_t p = 0; p < f.polygons.size(); ++p) {
        const Polygon& polygon = f.polygons[p];
        for (size_t r = 0; r <= polygon.holes.size(); ++r) {
          out.Start("Boundary").Attr("bndType", BoundaryType(f.mode, r)).Attr("edgeTrim", "true");
          out.Attr("name", f.name);
          RingAttrs(out, i, p, r);
          const Ring& ring = r == 0 ? polygon.shell : polygon.holes[r - 1];
          out.Start("PntList2D").Text(PointList2D(ring, true)).End().End();
        }
      }
    }
    out.End();
  }
  out.End();
}

void WritePoints(XmlOut& out, const Tin& tin) {
  out.Start("Pnts");
  std::string text;
  for (size_t i = 0; i < tin.vertices.size(); ++i) {
    const TinVertex& v = tin.vertices[i];
    out.Start("P").Attr("id", std::to_string(i + 1));
    if (v.kind != VertexKind::kDem) out.Attr("tb:kind", VertexKindName(v.kind));
    text.clear();
    AppendNumber(text, v.y);
    text += ' ';
    AppendNumber(text, v.x);
    text += ' ';
    AppendNumber(text, v.z);
    out.Text(text).End();
  }
  out.End();
}

void WriteFaces(XmlOut& out, const Tin& tin) {
  out.Start("Faces");
  std::string n, text;
  for (const TinTriangle& t : tin.triangles) {
    // LandXML's k-th neighbour lies across the edge from point k to point k+1, which is the edge
    // opposite tinbase's vertex k+2.
    n.clear();
    for (int k = 0; k < 3; ++k) {
      if (k > 0) n += ' ';
      const int32_t across = t.n[(k + 2) % 3];
      n += std::to_string(across == kNoNeighbour ? 0 : int64_t{across} + 1);
    }
    out.Start("F").Attr("n", n);
    if (!t.visible) out.Attr("i", "1");
    if (t.tag != kNoTag) out.Attr("tb:tag", std::to_string(t.tag));
    text = std::to_string(t.v[0] + 1) + ' ' + std::to_string(t.v[1] + 1) + ' ' +
           std::to_string(t.v[2] + 1);
    out.Text(text).End();
  }
  out.End();
}

void WriteDefinition(XmlOut& out, const Tin& tin) {
  out.Start("Definition").Attr("surfType", "TIN");
  if (!tin.vertices.empty()) {
    const auto [lo, hi] =
        std::minmax_element(tin.vertices.begin(), tin.vertices.end(),
                            [](const TinVertex& a, const TinVertex& b) { return a.z < b.z; });
    out.Attr("elevMin", Number(lo->z)).Attr("elevMax", Number(hi->z));
  }
  WritePoints(out, tin);
  WriteFaces(out, tin);
  out.End();
}

// The tinbase extension: tag values (tb:tag indexes them), the features' own columns and the
// constraint rows with their owners.
void WriteTinbaseFeature(XmlOut& out, const LandXmlSurface& s) {
  out.Start("Feature").Attr("code", "tinbase");
  for (const std::string& tag : s.tin.tags) out.Property("tag", tag);
  for (const LandXmlFeature& f : s.features) {
    out.Start("Feature").Attr("code", "tinbase:feature").Attr("name", f.name);
    out.Property("mode", FeatureModeName(f.mode));
    if (f.tag) out.Property("tag", *f.tag);
    if (f.level) out.Property("level", Number(*f.level));
    if (f.z_from == ZFrom::kFeature) out.Property("z_from", ZFromName(f.z_from));
    out.Property("attributes", f.attributes);
    out.End();
  }
  if (!s.constraints.empty()) {
    out.Start("Feature").Attr("code", "tinbase:constraints");
    for (const LandXmlConstraint& c : s.constraints) {
      out.Property("edge", std::to_string(c.a + 1) + ' ' + std::to_string(c.b + 1) + ' ' +
                               std::to_string(c.feature ? *c.feature + 1 : 0));
    }
    out.End();
  }
  out.End();
}

}  // namespace

LandXmlUnits UnitsFor(double metres_per_unit) {
  if (std::abs(metres_per_unit - 0.3048) < 1e-9) return {"Imperial", "foot"};
  if (std::abs(metres_per_unit - 1200.0 / 3937.0) < 1e-9) return {"Imperial", "USSurveyFoot"};
  return {"Metric", "meter"};
}

Status WriteLandXml(const LandXmlSurface& s, const std::string& path) {
  std::unique_ptr<xmlTextWriter, WriterDeleter> writer(xmlNewTextWriterFilename(path.c_str(), 0));
  if (!writer) return Status::IOError("cannot write " + path);
  XmlOut out(writer.get());
  out.Check(xmlTextWriterSetIndent(writer.get(), 1));
  out.Check(xmlTextWriterSetIndentString(writer.get(), reinterpret_cast<const xmlChar*>(" ")));
  out.Check(xmlTextWriterStartDocument(writer.get(), "1.0", "UTF-8", nullptr));
  out.Start("LandXML").Attr("xmlns", kLandXmlNamespace).Attr("xmlns:tb", kTinbaseLandXmlNamespace);
  out.Attr("version", "1.2").Attr("date", Today("%Y-%m-%d")).Attr("time", Today("%H:%M:%S"));
  WriteUnits(out, s.metres_per_unit);
  WriteCoordinateSystem(out, s);
  out.Start("Application").Attr("name", "tinbase").End();
  out.Start("Surfaces").Start("Surface").Attr("name", s.name);
  out.Attr("tb:kind", s.kind);
  if (!s.method.empty()) out.Attr("tb:method", s.method);
  if (s.tolerance) out.Attr("tb:tolerance", Number(*s.tolerance));
  if (!s.dem.empty()) out.Attr("tb:dem", s.dem);
  WriteSourceData(out, s);
  WriteDefinition(out, s.tin);
  WriteTinbaseFeature(out, s);
  out.End().End();  // Surface, Surfaces
  out.End();        // LandXML
  out.Check(xmlTextWriterEndDocument(writer.get()));
  const int flushed = xmlTextWriterFlush(writer.get());
  writer.reset();  // closes the file; its errors show in the flush and the calls before
  if (!out.ok() || flushed < 0) return Status::IOError("cannot write " + path);
  return Status::Ok();
}

}  // namespace tinbase
