// Boxes between coordinate systems, through OGRCoordinateTransformation::TransformBounds.
#include "service/crs_box.h"

#include <cpl_conv.h>
#include <ogr_spatialref.h>

#include <memory>

namespace tinbase::service {

namespace {

// Points per box edge: enough that a UTM edge's curve in degrees bulges past no densified point by
// more than a hair over a few hundred kilometres (GDAL's own default for TransformBounds).
constexpr int kDensifyPoints = 21;

// Longer than any CRS a client means (a WKT2 of a compound system is a few kilobytes).
constexpr size_t kMaxCrsText = 16384;

}  // namespace

Result<Box> TransformBox(const Box& box, const Crs& from, const Crs& to) {
  std::unique_ptr<OGRCoordinateTransformation> t(
      OGRCreateCoordinateTransformation(&from.ogr(), &to.ogr()));
  if (t == nullptr)
    return Status::InvalidArgument("no transformation from " + from.Label() + " to " + to.Label());
  Box out;
  if (!t->TransformBounds(box.min_x, box.min_y, box.max_x, box.max_y, &out.min_x, &out.min_y,
                          &out.max_x, &out.max_y, kDensifyPoints))
    return Status::InvalidArgument("the box " + std::to_string(box.min_x) + "," +
                                   std::to_string(box.min_y) + "," + std::to_string(box.max_x) +
                                   "," + std::to_string(box.max_y) + " of " + from.Label() +
                                   " does not transform to " + to.Label());
  return out;
}

Result<nlohmann::json> LonLatBox(const Box& box, const Crs& from) {
  TB_ASSIGN_OR_RETURN(const Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  TB_ASSIGN_OR_RETURN(const Box b, TransformBox(box, from, wgs84));
  return nlohmann::json::array({b.min_x, b.min_y, b.max_x, b.max_y});
}

Result<std::optional<Crs>> CrsParam(const httplib::Request& req) {
  if (!req.has_param("crs")) return std::optional<Crs>();
  const std::string text = req.get_param_value("crs");
  const auto unknown = [&] {
    return Status::InvalidArgument("parameter 'crs': '" + text.substr(0, 200) +
                                   "' is not a coordinate system GDAL knows");
  };
  // GDAL would also take a file name or a URL here and read it: not for a client's text.
  const char* const options[] = {"ALLOW_NETWORK_ACCESS=NO", "ALLOW_FILE_ACCESS=NO", nullptr};
  OGRSpatialReference srs;
  if (text.empty() || text.size() > kMaxCrsText ||
      srs.SetFromUserInput(text.c_str(), options) != OGRERR_NONE)
    return unknown();
  char* wkt = nullptr;
  const OGRErr exported = srs.exportToWkt(&wkt);
  const std::string wkt_text = wkt != nullptr ? wkt : "";
  CPLFree(wkt);
  if (exported != OGRERR_NONE) return unknown();
  auto crs = Crs::FromWkt(wkt_text);
  if (!crs.ok()) return unknown();
  return std::optional<Crs>(std::move(*crs));
}

}  // namespace tinbase::service
