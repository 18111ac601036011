#include "core/geometry/crs.h"

#include <ogr_spatialref.h>

#include <GeographicLib/UTMUPS.hpp>
#include <cmath>

namespace tinbase {

namespace {
std::unique_ptr<OGRSpatialReference> NewSrs() {
  auto srs = std::make_unique<OGRSpatialReference>();
  srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}
}  // namespace

Crs::Crs(std::unique_ptr<OGRSpatialReference> srs) : srs_(std::move(srs)) {}
Crs::Crs(const Crs& other) : srs_(NewSrs()) {
  *srs_ = *other.srs_;
  srs_->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
}
Crs& Crs::operator=(const Crs& other) {
  if (this != &other) {
    srs_ = NewSrs();
    *srs_ = *other.srs_;
    srs_->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }
  return *this;
}
Crs::Crs(Crs&&) noexcept = default;
Crs& Crs::operator=(Crs&&) noexcept = default;
Crs::~Crs() = default;

Result<Crs> Crs::FromUserInput(const std::string& text) {
  auto srs = NewSrs();
  if (text.empty() || srs->SetFromUserInput(text.c_str()) != OGRERR_NONE)
    return Status::InvalidArgument("unknown coordinate reference system '" + text + "'");
  return Crs(std::move(srs));
}

Result<Crs> Crs::FromWkt(const std::string& wkt) {
  if (wkt.empty()) return Status::InvalidArgument("no coordinate reference system");
  auto srs = NewSrs();
  if (srs->importFromWkt(wkt.c_str()) != OGRERR_NONE)
    return Status::InvalidArgument("unreadable coordinate reference system WKT");
  return Crs(std::move(srs));
}

Result<Crs> Crs::UtmFor(double lon, double lat) {
  if (!std::isfinite(lon) || !std::isfinite(lat) || std::abs(lat) > 84)
    return Status::InvalidArgument("no UTM zone for lon " + std::to_string(lon) + ", lat " +
                                   std::to_string(lat) + " (UTM covers 80S to 84N)");
  const int zone = GeographicLib::UTMUPS::StandardZone(lat, lon);
  const int epsg = (lat >= 0 ? 32600 : 32700) + zone;
  return FromUserInput("EPSG:" + std::to_string(epsg));
}

std::string Crs::Wkt() const {
  char* wkt = nullptr;
  const char* options[] = {"FORMAT=WKT2_2018", nullptr};
  srs_->exportToWkt(&wkt, options);
  std::string out = wkt != nullptr ? wkt : "";
  CPLFree(wkt);
  return out;
}

std::optional<int> Crs::Epsg() const {
  OGRSpatialReference copy(*srs_);
  const char* auth = copy.GetAuthorityName(nullptr);
  const char* code = copy.GetAuthorityCode(nullptr);
  if (auth == nullptr || code == nullptr) {
    if (copy.AutoIdentifyEPSG() == OGRERR_NONE) {
      auth = copy.GetAuthorityName(nullptr);
      code = copy.GetAuthorityCode(nullptr);
    }
  }
  if (auth != nullptr && code != nullptr && std::string(auth) == "EPSG") return std::atoi(code);
  return std::nullopt;
}

std::string Crs::Label() const {
  if (auto epsg = Epsg()) return "EPSG:" + std::to_string(*epsg);
  const char* name = srs_->GetName();
  return name != nullptr ? name : "unnamed CRS";
}

bool Crs::IsGeographic() const { return srs_->IsGeographic() != 0; }

double Crs::VerticalMetresPerUnit() const {
  if (srs_->IsCompound()) {
    const double vertical = srs_->GetTargetLinearUnits("VERT_CS", nullptr);
    if (vertical > 0) return vertical;
  }
  if (srs_->IsProjected()) {
    const double linear = srs_->GetLinearUnits(nullptr);
    if (linear > 0) return linear;
  }
  return 1.0;
}

bool Crs::IsSame(const Crs& other) const {
  const char* options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                           "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
  return srs_->IsSame(other.srs_.get(), options) != 0;
}

}  // namespace tinbase
