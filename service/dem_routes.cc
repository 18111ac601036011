// The DEM routes: the list of DEMs, the index map (a hillshade of an overview level), GeoTIFF
// windows read at the sampling step a cell budget allows, and paper 002's edge-collapsed TIN of
// a box as GLB. docs/api.md, "DEMs".
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/export/tin_export.h"
#include "db/dem_store.h"
#include "db/dem_window_tin.h"
#include "service/crs_box.h"
#include "service/dem_read.h"
#include "service/entity_tag.h"
#include "service/hillshade_png.h"
#include "service/json_reply.h"
#include "service/memory_file.h"
#include "service/request_params.h"
#include "service/routes.h"
#include "service/scratch_file.h"

namespace tinbase::service {

namespace {

// Limits of what one request may ask for; larger asks get 400 naming the range, so a client
// learns the bound instead of timing out.
constexpr int64_t kMaxOverviewSide = 4096;  // pixels
constexpr int64_t kDefaultOverviewSide = 1024;
constexpr int64_t kMaxClipCells = int64_t{1} << 24;  // 64 MiB of float32
constexpr int64_t kDefaultClipCells = int64_t{1} << 22;
constexpr int64_t kMaxTinCells = int64_t{1} << 20;      // 2 M triangles before the collapse
constexpr int64_t kDefaultTinCells = int64_t{1} << 16;  // a collapse of seconds
constexpr int64_t kMaxTinFaces = 2000000;
constexpr int64_t kDefaultTinFaces = 20000;

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

Box BoxOf(const GridGeometry& g) { return Box{g.MinX(), g.MinY(), g.MaxX(), g.MaxY()}; }

// 413 naming the limit when `bytes` is over the service's result limit; true when answered.
bool ReplyIfTooLarge(const ServiceContext& context, httplib::Response& res, size_t bytes,
                     const std::string& what, const std::string& advice) {
  const size_t limit = context.options().max_result_bytes;
  if (bytes <= limit) return false;
  ReplyError(res, 413, "too_large",
             what + " is " + std::to_string(bytes) + " bytes, over the service's limit of " +
                 std::to_string(limit) + ": " + advice);
  return true;
}

Result<nlohmann::json> DescribeDem(const DemInfo& dem) {
  TB_ASSIGN_OR_RETURN(const Crs crs, Crs::FromWkt(dem.crs_wkt));
  const Box box = BoxOf(dem.geometry);
  TB_ASSIGN_OR_RETURN(nlohmann::json lonlat, LonLatBox(box, crs));
  return nlohmann::json{{"name", dem.name},
                        {"width", dem.geometry.width},
                        {"height", dem.geometry.height},
                        {"cell_size", dem.geometry.cell_x},
                        {"bbox", {box.min_x, box.min_y, box.max_x, box.max_y}},
                        {"bbox_lonlat", lonlat},
                        {"levels", dem.levels},
                        {"crs", crs.Label()}};
}

void ListDems(ServiceContext& context, httplib::Response& res) {
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  DemStore dems(lease->store());
  auto list = dems.List();
  if (!list.ok()) return ReplyStatus(res, list.status());
  nlohmann::json out = nlohmann::json::array();
  for (const DemInfo& dem : *list) {
    auto j = DescribeDem(dem);
    if (!j.ok()) return ReplyStatus(res, j.status());
    out.push_back(std::move(*j));
  }
  ReplyJson(res, {{"dems", out}});
}

// The level the overview shows: `level` when given (it must fit in `size`), else the finest whose
// larger side fits.
Result<int> OverviewLevel(const DemInfo& dem, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(const int64_t size,
                      IntegerParam(req, "size", 16, kMaxOverviewSide, kDefaultOverviewSide));
  const auto side = [&](int level) {
    const GridGeometry& g = LevelOf(dem, level).geometry;
    return std::max(g.width, g.height);
  };
  if (req.has_param("level")) {
    TB_ASSIGN_OR_RETURN(const int64_t level, IntegerParam(req, "level", 0, dem.levels - 1));
    if (side(static_cast<int>(level)) > size)
      return Status::InvalidArgument(
          "parameter 'level': level " + std::to_string(level) + " is " +
          std::to_string(side(static_cast<int>(level))) + " cells on its longer side, more than " +
          "size " + std::to_string(size) + " (give a coarser level, a larger size up to " +
          std::to_string(kMaxOverviewSide) + ", or no level)");
    return static_cast<int>(level);
  }
  int level = dem.levels - 1;
  while (level > 0 && side(level - 1) <= size) --level;
  return level;
}

void GetOverview(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginDemRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  DemStore dems(read->store());
  const DemInfo& dem = read->dem;
  auto level = OverviewLevel(dem, req);
  if (!level.ok()) return ReplyStatus(res, level.status());
  const GridGeometry& g = LevelOf(dem, *level).geometry;
  auto grid = dems.ReadWindow(dem, DemBox{g.MinX(), g.MinY(), g.MaxX(), g.MaxY()}, *level);
  if (!grid.ok()) return ReplyStatus(res, grid.status());
  auto image = HillshadePng(*grid);
  if (!image.ok()) return ReplyStatus(res, image.status());
  const Box& b = image->lonlat;
  res.set_header("X-Tinbase-Bbox-Lonlat", Number(b.min_x) + "," + Number(b.min_y) + "," +
                                              Number(b.max_x) + "," + Number(b.max_y));
  res.set_header("X-Tinbase-Level", std::to_string(*level));
  if (ReplyNotModified(req, res, EntityTag(image->png, "png"), kRevalidate)) return;
  res.set_content(image->png, "image/png");
}

// The request's box in the DEM's CRS: `bbox` (required) in `crs` when given, else in the
// store's CRS.
Result<DemBox> RequestBox(const DemInfo& dem, const httplib::Request& req) {
  TB_ASSIGN_OR_RETURN(const std::optional<Box> given, BboxParam(req));
  if (!given) return Status::InvalidArgument("missing parameter 'bbox' (minx,miny,maxx,maxy)");
  if (!(given->min_x < given->max_x && given->min_y < given->max_y))
    return Status::InvalidArgument("parameter 'bbox': the box has no area (min must be below max)");
  TB_ASSIGN_OR_RETURN(const std::optional<Crs> crs, CrsParam(req));
  Box box = *given;
  if (crs) {
    TB_ASSIGN_OR_RETURN(const Crs store_crs, Crs::FromWkt(dem.crs_wkt));
    auto moved = TransformBox(box, *crs, store_crs);
    if (!moved.ok()) return moved.status().WithContext("parameter 'bbox'");
    box = *moved;
  }
  return DemBox{box.min_x, box.min_y, box.max_x, box.max_y};
}

void GetClip(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto read = BeginDemRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  DemStore dems(read->store());
  const DemInfo& dem = read->dem;
  auto box = RequestBox(dem, req);
  if (!box.ok()) return ReplyStatus(res, box.status());
  auto max_cells = IntegerParam(req, "max_cells", 1, kMaxClipCells, kDefaultClipCells);
  if (!max_cells.ok()) return ReplyStatus(res, max_cells.status());
  MemoryFile file(".tif");
  auto clip = dems.Clip(dem, *box, *max_cells, file.path());
  if (!clip.ok()) return ReplyStatus(res, clip.status());
  auto bytes = file.Read();
  if (!bytes.ok()) return ReplyStatus(res, bytes.status());
  if (ReplyIfTooLarge(context, res, bytes->size(), "the GeoTIFF", "ask for fewer max_cells"))
    return;
  res.set_header("X-Tinbase-Level", std::to_string(clip->level));
  res.set_header("X-Tinbase-Cells", std::to_string(clip->geometry.width) + "x" +
                                        std::to_string(clip->geometry.height));
  res.set_header("Content-Disposition", "attachment; filename=\"" + dem.name + "-clip.tif\"");
  res.set_content(*bytes, "image/tiff");
}

// "lon,lat,h" of the ENU frame's origin, read back from the GLB's asset.extras.tinbase.origin
// (core/export/glb_writer.h), so the header says exactly what the file was written against.
std::optional<std::string> GlbOrigin(const std::string& glb) {
  if (glb.size() < 20 || glb.compare(0, 4, "glTF") != 0) return std::nullopt;
  uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  if (json_length > glb.size() - 20) return std::nullopt;
  const auto gltf = nlohmann::json::parse(glb.substr(20, json_length), nullptr, false);
  const auto at = nlohmann::json::json_pointer("/asset/extras/tinbase/origin");
  if (gltf.is_discarded() || !gltf.contains(at)) return std::nullopt;
  const nlohmann::json& o = gltf[at];
  if (!o.contains("longitude") || !o.contains("latitude") || !o.contains("height"))
    return std::nullopt;
  return Number(o["longitude"].get<double>()) + "," + Number(o["latitude"].get<double>()) + "," +
         Number(o["height"].get<double>());
}

Result<DemWindowTinOptions> TinOptions(const httplib::Request& req) {
  DemWindowTinOptions options;
  TB_ASSIGN_OR_RETURN(options.faces, IntegerParam(req, "faces", 2, kMaxTinFaces, kDefaultTinFaces));
  TB_ASSIGN_OR_RETURN(options.max_cells,
                      IntegerParam(req, "max_cells", 4, kMaxTinCells, kDefaultTinCells));
  if (const std::optional<std::string> name = OptionalParam(req, "strategy")) {
    if (!ParseCollapseStrategy(*name, &options.strategy))
      return Status::InvalidArgument("parameter 'strategy': '" + *name +
                                     "' is not a strategy (expected quadric or paper)");
  }
  return options;
}

void GetTin(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto options = TinOptions(req);
  if (!options.ok()) return ReplyStatus(res, options.status());
  auto read = BeginDemRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  DemStore dems(read->store());
  const DemInfo& dem = read->dem;
  auto box = RequestBox(dem, req);
  if (!box.ok()) return ReplyStatus(res, box.status());
  auto tin = BuildDemWindowTin(dems, dem, *box, *options);
  if (!tin.ok()) return ReplyStatus(res, tin.status());
  auto crs = Crs::FromWkt(dem.crs_wkt);
  if (!crs.ok()) return ReplyStatus(res, crs.status());
  ScratchFile file(".glb");
  ExportOptions glb;
  glb.format = ExportFormat::kGlb;
  auto written = ExportTin(tin->tin, &*crs, file.path(), glb);
  if (!written.ok()) return ReplyStatus(res, written.status());
  auto bytes = file.Read();
  if (!bytes.ok()) return ReplyStatus(res, bytes.status());
  if (ReplyIfTooLarge(context, res, bytes->size(), "the GLB", "ask for fewer faces")) return;
  if (const std::optional<std::string> origin = GlbOrigin(*bytes))
    res.set_header("X-Tinbase-Origin", *origin);
  res.set_header("X-Tinbase-Level", std::to_string(tin->level));
  res.set_header("X-Tinbase-Faces", std::to_string(written->triangles));
  res.set_header("X-Tinbase-Faces-In", std::to_string(tin->collapse.faces_in));
  res.set_header("X-Tinbase-Max-Error", Number(tin->collapse.max_error));
  res.set_content(*bytes, "model/gltf-binary");
}

}  // namespace

void RegisterDemRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get("/dems", [&context](const httplib::Request&, httplib::Response& res) {
    ListDems(context, res);
  });
  server.Get(R"(/dems/([^/]+)/overview\.png)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetOverview(context, req, res);
             });
  server.Get(R"(/dems/([^/]+)/clip)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetClip(context, req, res);
             });
  server.Get(R"(/dems/([^/]+)/tin)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetTin(context, req, res);
             });
}

}  // namespace tinbase::service
