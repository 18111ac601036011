#include "core/import/landxml_reader.h"

#include <libxml/xmlreader.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include "core/base/number_text.h"
#include "core/geometry/predicates.h"

namespace tinbase {

namespace {

// ---- Small parsers of attribute and text values; each returns false on the first bad token.

std::vector<std::string_view> Tokens(std::string_view text) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    size_t j = i;
    while (j < text.size() && !std::isspace(static_cast<unsigned char>(text[j]))) ++j;
    if (j > i) out.push_back(text.substr(i, j - i));
    i = j;
  }
  return out;
}

// Exact: from_chars rounds correctly, so the writer's shortest text gives back the same double.
bool ToDouble(std::string_view s, double* v) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && !CheckNumber(*v);
}

bool ToInt(std::string_view s, int64_t* v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// ---- What the stream gives, before the cross-references are resolved.

struct RawFace {
  std::array<int64_t, 3> ids{};
  std::optional<std::array<int64_t, 3>> n;
  bool visible = true;
  int32_t tag = kNoTag;
  int line = 0;
};

struct RawRing {
  int64_t feature = 0;  // 1-based; 0 for a ring without the tinbase attributes
  int64_t polygon = 0;
  int64_t ring = 0;
  std::vector<Point2> points;
  std::vector<double> z;  // the elevations of a PntList3D; empty for a PntList2D
  int line = 0;
  std::string element;
};

struct RawConstraint {
  int64_t a = 0, b = 0, feature = 0;
  int line = 0;
};

struct OpenElement {
  std::string name;
  std::string code;  // a Feature's code attribute
};

struct XmlErrorSink {
  std::string message;
  int line = 0;
};

void OnXmlError(void* user, xmlErrorPtr error) {
  auto* sink = static_cast<XmlErrorSink*>(user);
  if (!sink->message.empty() || error == nullptr || error->level < XML_ERR_ERROR) return;
  sink->message = error->message != nullptr ? error->message : "unreadable";
  while (!sink->message.empty() && std::isspace(static_cast<unsigned char>(sink->message.back())))
    sink->message.pop_back();
  // Some of libxml2's messages span lines ("... encoding !\nBytes: ..."); an error is one line.
  for (char& c : sink->message)
    if (c == '\n' || c == '\r') c = ' ';
  sink->line = error->line;
}

struct ReaderDeleter {
  void operator()(xmlTextReader* r) const { xmlFreeTextReader(r); }
};

class Parser {
 public:
  explicit Parser(std::string path) : path_(std::move(path)) {}

  Result<LandXmlSurface> Run() {
    std::unique_ptr<xmlTextReader, ReaderDeleter> reader(xmlReaderForFile(
        path_.c_str(), nullptr,
        XML_PARSE_NONET | XML_PARSE_HUGE | XML_PARSE_BIG_LINES | XML_PARSE_NOWARNING));
    if (!reader) return Status::IOError("cannot open " + path_);
    r_ = reader.get();
    xmlTextReaderSetStructuredErrorHandler(r_, OnXmlError, &xml_error_);
    for (;;) {
      const int rc = xmlTextReaderRead(r_);
      if (rc < 0 || !xml_error_.message.empty()) return NotXml();
      if (rc == 0) break;
      const int type = xmlTextReaderNodeType(r_);
      if (type == XML_READER_TYPE_ELEMENT) {
        TB_RETURN_IF_ERROR(OnElement());
      } else if (type == XML_READER_TYPE_END_ELEMENT) {
        OnEnd();
      }
    }
    if (!saw_root_) return Error(1, "LandXML", "the file has no elements");
    return Finish();
  }

 private:
  // ---- Messages.
  Status Error(int line, const std::string& element, const std::string& what) const {
    return Status::InvalidArgument(path_ + ", line " + std::to_string(line) + ", <" + element +
                                   ">: " + what);
  }
  Status Here(const std::string& what) const { return Error(Line(), name_, what); }
  Status NotXml() const {
    const std::string what = xml_error_.message.empty() ? "unreadable" : xml_error_.message;
    return Status::InvalidArgument(path_ + ", line " +
                                   std::to_string(std::max(1, xml_error_.line)) +
                                   ": not well-formed XML: " + what);
  }
  int Line() const { return static_cast<int>(xmlGetLineNo(xmlTextReaderCurrentNode(r_))); }

  // ---- Attribute and text access on the current element.
  std::optional<std::string> Attr(const char* name, bool tinbase = false) const {
    xmlChar* v = tinbase ? xmlTextReaderGetAttributeNs(
                               r_, reinterpret_cast<const xmlChar*>(name),
                               reinterpret_cast<const xmlChar*>(kTinbaseLandXmlNamespace))
                         : xmlTextReaderGetAttribute(r_, reinterpret_cast<const xmlChar*>(name));
    if (v == nullptr) return std::nullopt;
    std::string s(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return s;
  }
  std::string Text() const {
    xmlChar* v = xmlTextReaderReadString(r_);
    if (v == nullptr) return {};
    std::string s(reinterpret_cast<const char*>(v));
    xmlFree(v);
    return s;
  }
  // The whole number in attribute `name` (nullopt when absent), at least `min`.
  Result<std::optional<int64_t>> IntAttr(const char* name, bool tinbase, int64_t min) const {
    const auto text = Attr(name, tinbase);
    if (!text) return std::optional<int64_t>();
    int64_t v = 0;
    if (!ToInt(*text, &v) || v < min)
      return Here(std::string("attribute ") + (tinbase ? "tb:" : "") + name + " is '" + *text +
                  "', not a whole number of at least " + std::to_string(min));
    return std::optional<int64_t>(v);
  }
  Result<std::vector<double>> Numbers(const std::string& text, size_t multiple_of,
                                      const std::string& what) const {
    std::vector<double> out;
    for (std::string_view token : Tokens(text)) {
      double v = 0;
      if (!ToDouble(token, &v)) return Here("'" + std::string(token) + "' is not a number");
      out.push_back(v);
    }
    if (out.empty() || out.size() % multiple_of != 0)
      return Here("expected " + what + ", got " + std::to_string(out.size()) + " numbers");
    return out;
  }
  Result<std::array<int64_t, 3>> ThreeInts(const std::string& text, int64_t min,
                                           const std::string& what) const {
    const auto tokens = Tokens(text);
    if (tokens.size() != 3)
      return Here(what + ": expected 3 whole numbers, got " + std::to_string(tokens.size()));
    std::array<int64_t, 3> out{};
    for (int k = 0; k < 3; ++k) {
      if (!ToInt(tokens[k], &out[k]) || out[k] < min)
        return Here(what + ": '" + std::string(tokens[k]) + "' is not a whole number of at least " +
                    std::to_string(min));
    }
    return out;
  }

  // ---- The stream.
  Status OnElement() {
    name_ = reinterpret_cast<const char*>(xmlTextReaderConstLocalName(r_));
    const std::string parent = stack_.empty() ? "" : stack_.back().name;
    const bool empty = xmlTextReaderIsEmptyElement(r_) != 0;
    OpenElement open{name_, name_ == "Feature" ? Attr("code").value_or("") : ""};
    if (stack_.empty()) {
      saw_root_ = true;
      if (name_ != "LandXML")
        return Here("not a LandXML file: the root element is <" + name_ + ">");
    }
    if (skip_depth_ == 0) {
      if (name_ == "Surface" && parent == "Surfaces" && surface_done_) skip_depth_ = 1;
      if (skip_depth_ == 0) TB_RETURN_IF_ERROR(Handle(parent, open.code));
    } else {
      ++skip_depth_;
    }
    if (!empty) {
      stack_.push_back(std::move(open));
    } else if (skip_depth_ > 0) {
      --skip_depth_;
    }
    return Status::Ok();
  }

  void OnEnd() {
    if (stack_.empty()) return;
    if (skip_depth_ > 0) --skip_depth_;
    if (stack_.back().name == "Surface" && in_surface_) {
      in_surface_ = false;
      surface_done_ = true;
    }
    stack_.pop_back();
  }

  // The code of the innermost open Feature element, or "".
  std::string FeatureCode() const {
    for (auto it = stack_.rbegin(); it != stack_.rend(); ++it)
      if (it->name == "Feature") return it->code;
    return "";
  }

  Status Handle(const std::string& parent, const std::string& code) {
    if (parent == "Units" && (name_ == "Metric" || name_ == "Imperial")) return OnUnits();
    if (name_ == "CoordinateSystem" && parent == "LandXML") return OnCoordinateSystem();
    if (name_ == "Surface" && parent == "Surfaces") return OnSurface();
    if (!in_surface_) return Status::Ok();
    if (name_ == "Definition" && parent == "Surface") {
      has_definition_ = true;
      return Status::Ok();
    }
    if (name_ == "P" && parent == "Pnts") return OnPoint();
    if (name_ == "F" && parent == "Faces") return OnFace();
    if ((name_ == "PntList2D" || name_ == "PntList3D") &&
        (parent == "Breakline" || parent == "Boundary"))
      return OnRing(parent);
    if (name_ == "Breakline" || name_ == "Boundary") return OnRingParent();
    if (name_ == "Feature") return OnFeature(parent, code);
    if (name_ == "Property" && parent == "Feature") return OnProperty();
    return Status::Ok();
  }

  Status OnUnits() {
    const std::string unit = Attr("linearUnit").value_or("meter");
    if (unit == "foot") out_.metres_per_unit = 0.3048;
    if (unit == "USSurveyFoot") out_.metres_per_unit = 1200.0 / 3937.0;
    return Status::Ok();
  }

  Status OnCoordinateSystem() {
    out_.crs_wkt = Attr("ogcWktCode").value_or("");
    out_.crs_name = Attr("name").value_or("");
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> epsg, IntAttr("epsgCode", false, 1));
    if (epsg) out_.epsg = static_cast<int>(*epsg);
    return Status::Ok();
  }

  Status OnSurface() {
    in_surface_ = true;
    out_.name = Attr("name").value_or("");
    out_.kind = Attr("kind", true).value_or("free");
    if (out_.kind != "free" && out_.kind != "delaunay")
      return Here("attribute tb:kind is '" + out_.kind + "', not 'delaunay' or 'free'");
    out_.method = Attr("method", true).value_or("landxml");
    out_.dem = Attr("dem", true).value_or("");
    if (const auto tol = Attr("tolerance", true)) {
      double v = 0;
      if (!ToDouble(*tol, &v) || v < 0)
        return Here("attribute tb:tolerance is '" + *tol + "', not a number of at least 0");
      out_.tolerance = v;
    }
    return Status::Ok();
  }

  Status OnPoint() {
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> id, IntAttr("id", false, 1));
    if (!id) return Here("a point needs an id");
    TB_ASSIGN_OR_RETURN(std::vector<double> yxz, Numbers(Text(), 3, "northing easting elevation"));
    if (yxz.size() != 3)
      return Here("expected northing easting elevation, got " + std::to_string(yxz.size()) +
                  " numbers");
    TinVertex v{yxz[1], yxz[0], yxz[2], VertexKind::kDem};
    if (const auto kind = Attr("kind", true)) {
      if (!ParseVertexKind(*kind, &v.kind))
        return Here("attribute tb:kind is '" + *kind + "', not a vertex kind");
    }
    const auto [it, inserted] =
        point_index_.emplace(*id, static_cast<uint32_t>(out_.tin.vertices.size()));
    if (!inserted)
      return Here("point id " + std::to_string(*id) + " is used twice (first at line " +
                  std::to_string(point_lines_[it->second]) + ")");
    out_.tin.vertices.push_back(v);
    point_lines_.push_back(Line());
    return Status::Ok();
  }

  Status OnFace() {
    RawFace f;
    f.line = Line();
    TB_ASSIGN_OR_RETURN(f.ids, ThreeInts(Text(), 1, "point ids"));
    if (const auto n = Attr("n")) {
      TB_ASSIGN_OR_RETURN(f.n, ThreeInts(*n, 0, "attribute n"));
    }
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> invisible, IntAttr("i", false, 0));
    if (invisible && *invisible > 1) return Here("attribute i is not 0 or 1");
    f.visible = !invisible || *invisible == 0;
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> tag, IntAttr("tag", true, 0));
    if (tag) {
      if (*tag > INT32_MAX) return Here("attribute tb:tag is out of range");
      f.tag = static_cast<int32_t>(*tag);
    }
    faces_.push_back(f);
    return Status::Ok();
  }

  Status OnRing(const std::string& parent) {
    // The attributes are on the parent Breakline/Boundary, read when it was opened.
    RawRing ring = pending_ring_;
    ring.line = Line();
    ring.element = parent;
    const size_t dims = name_ == "PntList3D" ? 3 : 2;
    TB_ASSIGN_OR_RETURN(
        std::vector<double> values,
        Numbers(Text(), dims,
                dims == 3 ? "northing easting elevation triples" : "northing easting pairs"));
    for (size_t i = 0; i < values.size(); i += dims) {
      ring.points.push_back({values[i + 1], values[i]});
      if (dims == 3) ring.z.push_back(values[i + 2]);
    }
    if (ring.feature > 0) rings_.push_back(std::move(ring));
    return Status::Ok();
  }

  Status OnFeature(const std::string& parent, const std::string& code) {
    if (parent == "Surface" && code == "tinbase") return Status::Ok();
    if (FeatureCode() != "tinbase") return Status::Ok();
    if (code == "tinbase:feature") {
      LandXmlFeature f;
      f.name = Attr("name").value_or("");
      features_.push_back({std::move(f), Line(), false});
    }
    return Status::Ok();
  }

  Status OnProperty() {
    const std::string code = FeatureCode();
    const std::string label = Attr("label").value_or("");
    const auto value = Attr("value");
    if (!value) return Here("a Property needs a value");
    if (code == "tinbase" && label == "tag") {
      out_.tin.tags.push_back(*value);
    } else if (code == "tinbase:feature" && !features_.empty()) {
      TB_RETURN_IF_ERROR(OnFeatureProperty(features_.back(), label, *value));
    } else if (code == "tinbase:constraints" && label == "edge") {
      TB_ASSIGN_OR_RETURN(const auto abf, ThreeInts(*value, 0, "edge"));
      if (abf[0] < 1 || abf[1] < 1) return Here("edge: point ids start at 1");
      constraints_.push_back({abf[0], abf[1], abf[2], Line()});
    }
    return Status::Ok();
  }

  struct RawFeature {
    LandXmlFeature feature;
    int line = 0;
    bool has_mode = false;
  };

  Status OnFeatureProperty(RawFeature& raw, const std::string& label, const std::string& value) {
    LandXmlFeature& f = raw.feature;
    if (label == "mode") {
      auto mode = ParseFeatureMode(value);
      if (!mode.ok()) return Here(mode.status().message());
      f.mode = *mode;
      raw.has_mode = true;
    } else if (label == "tag") {
      f.tag = value;
    } else if (label == "level") {
      double v = 0;
      if (!ToDouble(value, &v)) return Here("level '" + value + "' is not a number");
      f.level = v;
    } else if (label == "attributes") {
      f.attributes = value;
    } else if (label == "z_from") {
      auto z_from = ParseZFrom(value);
      if (!z_from.ok()) return Here(z_from.status().message());
      f.z_from = *z_from;
    }
    return Status::Ok();
  }

  // Remembers a Breakline's or Boundary's tinbase attributes for its point list.
  Status OnRingParent() {
    pending_ring_ = RawRing{};
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> feature, IntAttr("feature", true, 1));
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> polygon, IntAttr("polygon", true, 0));
    TB_ASSIGN_OR_RETURN(std::optional<int64_t> ring, IntAttr("ring", true, 0));
    pending_ring_.feature = feature.value_or(0);
    pending_ring_.polygon = polygon.value_or(0);
    pending_ring_.ring = ring.value_or(0);
    return Status::Ok();
  }

  // ---- Cross-references, once the stream is read.
  Result<LandXmlSurface> Finish() {
    if (!has_definition_)
      return Status::InvalidArgument(path_ +
                                     ": no Surfaces/Surface/Definition (a TIN) in the file");
    if (faces_.empty())
      return Status::InvalidArgument(path_ + ": the Surface/Definition has no faces (<F>)");
    TB_RETURN_IF_ERROR(ResolveFaces());
    TB_RETURN_IF_ERROR(LinkFaces());
    TB_RETURN_IF_ERROR(ResolveFeatures());
    TB_RETURN_IF_ERROR(ResolveConstraints());
    return std::move(out_);
  }

  Status ResolveFaces() {
    const auto& vs = out_.tin.vertices;
    out_.tin.triangles.reserve(faces_.size());
    for (const RawFace& f : faces_) {
      TinTriangle t;
      for (int k = 0; k < 3; ++k) {
        auto it = point_index_.find(f.ids[k]);
        if (it == point_index_.end())
          return Error(
              f.line, "F",
              "face refers to point " + std::to_string(f.ids[k]) + ", which is not in Pnts");
        t.v[k] = it->second;
      }
      const auto p = [&](int k) { return Point2{vs[t.v[k]].x, vs[t.v[k]].y}; };
      const int turn = Orientation(p(0), p(1), p(2));
      if (turn == 0) return Error(f.line, "F", "the face's points are collinear (or repeated)");
      if (turn < 0) std::swap(t.v[1], t.v[2]);  // clockwise in the file: turn it
      t.visible = f.visible;
      if (f.tag != kNoTag && f.tag >= static_cast<int32_t>(out_.tin.tags.size()))
        return Error(f.line, "F",
                     "tb:tag " + std::to_string(f.tag) + " is not one of the " +
                         std::to_string(out_.tin.tags.size()) + " tags");
      t.tag = f.tag;
      out_.tin.triangles.push_back(t);
    }
    return Status::Ok();
  }

  // Neighbours from shared edges (each directed edge used once; its reverse, if any, is the
  // neighbour), then checked against the faces' `n`.
  Status LinkFaces() {
    auto& ts = out_.tin.triangles;
    struct Edge {
      uint32_t a, b, face;
      int opposite;  // index in the face of the vertex across the edge
    };
    std::vector<Edge> edges;
    edges.reserve(ts.size() * 3);
    for (uint32_t t = 0; t < ts.size(); ++t)
      for (int k = 0; k < 3; ++k)
        edges.push_back({ts[t].v[(k + 1) % 3], ts[t].v[(k + 2) % 3], t, k});
    const auto key = [](const Edge& e) { return std::tie(e.a, e.b); };
    // Stable, so that of two faces repeating an edge the later one in the file is named.
    std::stable_sort(edges.begin(), edges.end(),
                     [&](const Edge& x, const Edge& y) { return key(x) < key(y); });
    for (size_t i = 1; i < edges.size(); ++i) {
      if (key(edges[i]) == key(edges[i - 1]))
        return Error(faces_[edges[i].face].line, "F",
                     "the face shares an edge in the same direction with the face at line " +
                         std::to_string(faces_[edges[i - 1].face].line) +
                         " (overlapping faces, or faces wound both ways)");
    }
    for (const Edge& e : edges) {
      auto it = std::lower_bound(edges.begin(), edges.end(), Edge{e.b, e.a, 0, 0},
                                 [&](const Edge& x, const Edge& y) { return key(x) < key(y); });
      if (it != edges.end() && it->a == e.b && it->b == e.a)
        ts[e.face].n[e.opposite] = static_cast<int32_t>(it->face);
    }
    for (size_t t = 0; t < ts.size(); ++t) {
      const RawFace& f = faces_[t];
      if (!f.n) continue;
      for (int k = 0; k < 3; ++k) {
        // The file's k-th neighbour is across (p_k, p_k+1): opposite p_k+2, wherever the turn
        // of a clockwise face put it.
        const uint32_t across_from = point_index_.at(f.ids[(k + 2) % 3]);
        const int j = static_cast<int>(std::find(ts[t].v.begin(), ts[t].v.end(), across_from) -
                                       ts[t].v.begin());
        const int64_t expected = ts[t].n[j] == kNoNeighbour ? 0 : int64_t{ts[t].n[j]} + 1;
        if ((*f.n)[k] != expected)
          return Error(
              f.line, "F",
              "attribute n names face " + std::to_string((*f.n)[k]) + " across edge " +
                  std::to_string(k + 1) + ", but the faces put " +
                  (expected == 0 ? std::string("none") : "face " + std::to_string(expected)) +
                  " there");
      }
    }
    return Status::Ok();
  }

  Status ResolveFeatures() {
    for (const RawFeature& raw : features_) {
      if (!raw.has_mode)
        return Error(raw.line, "Feature", "a tinbase:feature needs a mode Property");
      out_.features.push_back(raw.feature);
    }
    // (feature, polygon) -> rings by index, each as read (closed for polygons).
    std::map<std::pair<int64_t, int64_t>, std::map<int64_t, const RawRing*>> polygons;
    for (const RawRing& ring : rings_) {
      if (ring.feature > static_cast<int64_t>(out_.features.size()))
        return Error(ring.line, ring.element,
                     "tb:feature " + std::to_string(ring.feature) + " is not one of the " +
                         std::to_string(out_.features.size()) + " tinbase features");
      auto& slot = polygons[{ring.feature, ring.polygon}][ring.ring];
      if (slot != nullptr)
        return Error(ring.line, ring.element,
                     "ring " + std::to_string(ring.ring) + " of polygon " +
                         std::to_string(ring.polygon) + " is given twice");
      slot = &ring;
    }
    for (const auto& [fp, rings] : polygons) {
      LandXmlFeature& f = out_.features[fp.first - 1];
      const RawRing& first = *rings.begin()->second;
      if (IsLineMode(f.mode)) {
        if (rings.size() != 1 || first.points.size() < 2)
          return Error(first.line, first.element, "a breakline is one line of 2 or more points");
        if (f.z_from == ZFrom::kFeature && first.z.empty())
          return Error(first.line, first.element,
                       "a line of a feature with z_from 'feature' needs its z (a PntList3D)");
        f.lines.push_back(first.points);
        if (f.z_from == ZFrom::kFeature) f.line_z.push_back(first.z);
        continue;
      }
      std::vector<Ring> read;
      int64_t expect = 0;
      for (const auto& [index, ring] : rings) {
        if (index != expect++)
          return Error(ring->line, ring->element,
                       "ring " + std::to_string(expect - 1) + " of this polygon is missing");
        read.push_back(ring->points);
      }
      auto polygon = MakeValidPolygon(read);
      if (!polygon.ok())
        return Error(first.line, first.element,
                     "feature " + std::to_string(fp.first) + ", polygon " +
                         std::to_string(fp.second) + ": " + polygon.status().message());
      f.polygons.push_back(std::move(*polygon));
    }
    for (size_t i = 0; i < features_.size(); ++i) {
      const LandXmlFeature& f = out_.features[i];
      if (f.polygons.empty() && f.lines.empty())
        return Error(features_[i].line, "Feature",
                     "tinbase feature " + std::to_string(i + 1) + " has no rings in SourceData");
    }
    return Status::Ok();
  }

  Status ResolveConstraints() {
    for (const RawConstraint& c : constraints_) {
      auto a = point_index_.find(c.a), b = point_index_.find(c.b);
      if (a == point_index_.end() || b == point_index_.end())
        return Error(c.line, "Property",
                     "edge refers to point " + std::to_string(a == point_index_.end() ? c.a : c.b) +
                         ", which is not in Pnts");
      if (c.feature > static_cast<int64_t>(out_.features.size()))
        return Error(
            c.line, "Property",
            "edge refers to tinbase feature " + std::to_string(c.feature) + ", which is not there");
      LandXmlConstraint out{a->second, b->second, std::nullopt};
      if (c.feature > 0) out.feature = static_cast<uint32_t>(c.feature - 1);
      out_.constraints.push_back(out);
    }
    return Status::Ok();
  }

  std::string path_;
  xmlTextReader* r_ = nullptr;
  XmlErrorSink xml_error_;
  std::vector<OpenElement> stack_;
  std::string name_;
  bool saw_root_ = false;
  bool in_surface_ = false;
  bool surface_done_ = false;
  bool has_definition_ = false;
  int skip_depth_ = 0;

  LandXmlSurface out_;
  std::unordered_map<int64_t, uint32_t> point_index_;
  std::vector<int> point_lines_;
  std::vector<RawFace> faces_;
  RawRing pending_ring_;
  std::vector<RawRing> rings_;
  std::vector<RawFeature> features_;
  std::vector<RawConstraint> constraints_;
};

}  // namespace

Result<LandXmlSurface> ReadLandXml(const std::string& path) {
  xmlInitParser();  // idempotent; makes libxml2's global set-up thread-safe before first use
  Parser parser(path);
  return parser.Run();
}

}  // namespace tinbase
