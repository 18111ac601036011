#include "core/tin/feature_paint.h"

#include <cassert>

#include "core/geometry/polygon_locator.h"

namespace tinbase {

namespace {

Point2 Centroid(const Tin& tin, const TinTriangle& t) {
  const TinVertex& a = tin.vertices[t.v[0]];
  const TinVertex& b = tin.vertices[t.v[1]];
  const TinVertex& c = tin.vertices[t.v[2]];
  return {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
}

// Each triangle's centroid is located once per feature; the locator's bounding-box test makes
// features far away nearly free.
std::vector<uint8_t> InsideTriangles(const Tin& tin, const std::vector<Point2>& centroids,
                                     const PolygonLocator& locator) {
  std::vector<uint8_t> inside(tin.triangles.size(), 0);
  for (size_t t = 0; t < centroids.size(); ++t)
    inside[t] = locator.Locate(centroids[t]) != PointInPolygon::kOutside;
  return inside;
}

}  // namespace

const char* PaintModeName(PaintMode mode) {
  switch (mode) {
    case PaintMode::kClip:
      return "clip";
    case PaintMode::kErase:
      return "erase";
    case PaintMode::kFill:
      return "fill";
    case PaintMode::kReplace:
      return "replace";
  }
  return "fill";
}

Result<PaintMode> ParsePaintMode(const std::string& name) {
  for (PaintMode mode :
       {PaintMode::kClip, PaintMode::kErase, PaintMode::kFill, PaintMode::kReplace})
    if (name == PaintModeName(mode)) return mode;
  return Status::InvalidArgument("unknown paint mode '" + name +
                                 "' (expected clip, erase, fill or replace)");
}

Paint ComputePaint(const Tin& tin, const std::vector<PaintedFeature>& features) {
  const size_t n = tin.triangles.size();
  Paint paint;
  paint.visible.assign(n, 1);
  paint.tag.assign(n, kNoTag);
  std::vector<Point2> centroids(n);
  for (size_t t = 0; t < n; ++t) centroids[t] = Centroid(tin, tin.triangles[t]);

  // Clip polygons act as one union; with none, clipping hides nothing.
  std::vector<uint8_t> in_clip;
  std::vector<uint8_t> replaced(tin.vertices.size(), 0);
  std::vector<double> level(tin.vertices.size(), 0);
  for (const PaintedFeature& feature : features) {
    assert(feature.tag == kNoTag ||
           (feature.tag >= 0 && static_cast<size_t>(feature.tag) < tin.tags.size()));
    const PolygonLocator locator(feature.polygons);
    const std::vector<uint8_t> inside = feature.polygons.empty()
                                            ? std::vector<uint8_t>(n, 0)
                                            : InsideTriangles(tin, centroids, locator);
    switch (feature.mode) {
      case PaintMode::kClip:
        if (in_clip.empty()) in_clip.assign(n, 0);
        for (size_t t = 0; t < n; ++t) in_clip[t] |= inside[t];
        break;
      case PaintMode::kErase:
        for (size_t t = 0; t < n; ++t)
          if (inside[t]) paint.visible[t] = 0;
        break;
      case PaintMode::kReplace:
        // A vertex on the ring is part of the flat replaced area, so boundary counts.
        for (uint32_t v = 0; v < tin.vertices.size(); ++v) {
          const TinVertex& p = tin.vertices[v];
          if (locator.Locate({p.x, p.y}) == PointInPolygon::kOutside) continue;
          replaced[v] = 1;
          level[v] = feature.level;
        }
        [[fallthrough]];
      case PaintMode::kFill:
        for (size_t t = 0; t < n; ++t)
          if (inside[t]) paint.tag[t] = feature.tag;
        break;
    }
  }
  if (!in_clip.empty()) {
    for (size_t t = 0; t < n; ++t)
      if (!in_clip[t]) paint.visible[t] = 0;
  }
  for (uint32_t v = 0; v < tin.vertices.size(); ++v)
    if (replaced[v]) paint.levels.push_back({v, level[v]});
  return paint;
}

void ApplyPaint(const Paint& paint, Tin& tin, bool apply_levels) {
  assert(paint.visible.size() == tin.triangles.size() && paint.tag.size() == tin.triangles.size());
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    tin.triangles[t].visible = paint.visible[t] != 0;
    tin.triangles[t].tag = paint.tag[t];
  }
  if (!apply_levels) return;
  for (const VertexLevel& level : paint.levels) tin.vertices[level.vertex].z = level.z;
}

}  // namespace tinbase
