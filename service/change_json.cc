// Change log rows as JSON, with the changed box in lon/lat for web clients.
#include "service/change_json.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "db/surface_store.h"

namespace tinbase::service {

void ChangeJson::TransformDeleter::operator()(OGRCoordinateTransformation* t) const {
  OGRCoordinateTransformation::DestroyCT(t);
}

Result<ChangeJson> ChangeJson::For(Store& store) {
  ChangeJson out;
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  if (!crs) return out;
  TB_ASSIGN_OR_RETURN(Crs lonlat, Crs::FromUserInput("EPSG:4326"));
  OGRCoordinateTransformation* t = OGRCreateCoordinateTransformation(&crs->ogr(), &lonlat.ogr());
  if (t != nullptr) out.to_lonlat_.reset(t, TransformDeleter());
  return out;
}

nlohmann::json ChangeJson::LonLatBox(double min_x, double min_y, double max_x, double max_y) const {
  if (!to_lonlat_) return nullptr;
  const double mid_x = 0.5 * (min_x + max_x), mid_y = 0.5 * (min_y + max_y);
  std::vector<double> x = {min_x, mid_x, max_x, min_x, max_x, min_x, mid_x, max_x};
  std::vector<double> y = {min_y, min_y, min_y, mid_y, mid_y, max_y, max_y, max_y};
  std::vector<int> ok(x.size(), 0);
  to_lonlat_->Transform(static_cast<int>(x.size()), x.data(), y.data(), nullptr, ok.data());
  for (size_t i = 0; i < x.size(); ++i)
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i])) return nullptr;
  return {*std::min_element(x.begin(), x.end()), *std::min_element(y.begin(), y.end()),
          *std::max_element(x.begin(), x.end()), *std::max_element(y.begin(), y.end())};
}

Result<nlohmann::json> ChangeJson::Describe(Store& store, const Change& change) {
  nlohmann::json j = {{"tx", change.tx},
                      {"time", change.time},
                      {"action", change.action},
                      {"removed", change.removed},
                      {"added", change.added}};
  j["surface"] = nullptr;
  if (change.surface) {
    auto known = surface_names_.find(*change.surface);
    if (known == surface_names_.end()) {
      auto surface = SurfaceStore(store).FindById(*change.surface);
      // A surface deleted since keeps its id in the log; its name is gone.
      if (!surface.ok() && surface.status().code() != StatusCode::kNotFound)
        return surface.status();
      known = surface_names_.emplace(*change.surface, surface.ok() ? surface->name : "").first;
    }
    if (!known->second.empty()) j["surface"] = known->second;
  }
  j["feature"] = change.feature ? nlohmann::json(*change.feature) : nlohmann::json(nullptr);
  const bool has_box = change.min_x <= change.max_x && change.min_y <= change.max_y &&
                       std::isfinite(change.min_x) && std::isfinite(change.max_x) &&
                       std::isfinite(change.min_y) && std::isfinite(change.max_y);
  j["bbox"] = has_box ? nlohmann::json{change.min_x, change.min_y, change.max_x, change.max_y}
                      : nlohmann::json(nullptr);
  j["bbox_lonlat"] = has_box ? LonLatBox(change.min_x, change.min_y, change.max_x, change.max_y)
                             : nlohmann::json(nullptr);
  return j;
}

}  // namespace tinbase::service
