#include "db/contour_import.h"

#include <cpl_vsi.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "core/base/number_text.h"
#include "core/raster/gdal_raster.h"
#include "core/vector/polygon_source.h"

namespace tinbase {
namespace {

std::string FileName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

// The elevation of a line: a JSON number, or a string that is entirely a finite number (text
// fields of shapefiles and CSV often carry them).
Result<double> Level(const LineFeature& feature, const std::string& field) {
  const nlohmann::json& value = feature.attributes.at(field);
  const std::string where = feature.label + ": field '" + field + "'";
  if (value.is_null()) return Status::InvalidArgument(where + " is empty");
  if (value.is_number()) {
    const double level = value.get<double>();
    if (!CheckNumber(level)) return level;
  } else if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    char* end = nullptr;
    const double level = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size() && !CheckNumber(level)) return level;
  }
  return Status::InvalidArgument(where + " is not a number (" + value.dump() + ")");
}

Result<std::vector<ContourLine>> ToContours(const std::vector<LineFeature>& features,
                                            const ContourImportOptions& options) {
  std::vector<ContourLine> lines;
  for (const LineFeature& feature : features) {
    if (!feature.attributes.contains(options.field)) {
      std::string names;
      for (const auto& [name, value] : feature.attributes.items())
        names += (names.empty() ? "" : ", ") + name;
      return Status::InvalidArgument(FileName(options.path) + ": no field '" + options.field +
                                     "' (fields: " + names + ")");
    }
    TB_ASSIGN_OR_RETURN(const double level, Level(feature, options.field));
    for (size_t k = 0; k < feature.lines.size(); ++k) {
      ContourLine line;
      line.label =
          feature.lines.size() == 1 ? feature.label : feature.label + ", line " + std::to_string(k);
      line.level = level;
      line.points = feature.lines[k];
      lines.push_back(std::move(line));
    }
  }
  return lines;
}

// A /vsimem file that GDAL forgets when this object dies.
class MemFile {
 public:
  explicit MemFile(const std::string& stem) {
    static std::atomic<int> counter{0};
    path_ = "/vsimem/tinbase_contours_" + std::to_string(counter++) + "/" + stem + ".tif";
  }
  ~MemFile() { VSIUnlink(path_.c_str()); }
  MemFile(const MemFile&) = delete;
  MemFile& operator=(const MemFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace

Result<ContourImportReport> ImportContourDem(Store& store, const ContourImportOptions& options) {
  if (options.name.empty()) return Status::InvalidArgument("the new DEM needs a name");
  if (!(options.cell > 0) || !std::isfinite(options.cell))
    return Status::InvalidArgument("cell size must be a positive number");
  if (options.field.empty())
    return Status::InvalidArgument(FileName(options.path) + ": name the elevation field");
  DemStore dems(store);
  if (dems.Find(options.name).ok())
    return Status::Conflict("a DEM named '" + options.name + "' already exists");

  VectorSourceOptions source;
  source.layer = options.layer;
  TB_ASSIGN_OR_RETURN(std::optional<Crs> store_crs, store.GetCrs());
  std::string crs_wkt;
  if (store_crs) {
    source.target_crs = *store_crs;
    crs_wkt = store_crs->Wkt();
  } else {
    TB_ASSIGN_OR_RETURN(std::optional<Crs> source_crs, ReadVectorCrs(options.path, source));
    if (!source_crs)
      return Status::InvalidArgument(FileName(options.path) +
                                     ": source has no CRS and the store has none yet");
    crs_wkt = source_crs->Wkt();
  }
  TB_ASSIGN_OR_RETURN(std::vector<LineFeature> features, ReadLineFeatures(options.path, source));
  TB_ASSIGN_OR_RETURN(std::vector<ContourLine> lines, ToContours(features, options));

  ContourImportReport report;
  TB_ASSIGN_OR_RETURN(Grid grid, DemFromContours(lines, options.cell, &report.contours));
  grid.crs_wkt = crs_wkt;
  const MemFile file(options.name);
  TB_RETURN_IF_ERROR(WriteGeoTiff(grid, file.path()));
  DemImportOptions import;
  import.name = options.name;
  import.block_size = options.block_size;
  TB_ASSIGN_OR_RETURN(report.dem, dems.Import({file.path()}, import));
  return report;
}

}  // namespace tinbase
