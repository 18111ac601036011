// Kernels: `measure area|volume|cutfill|slope` (areas per tag, volume against a level, cut and
// fill between two surfaces, slope and aspect per triangle) and `contours` (contour lines as an
// OGR layer). All read the visible part of a surface; results are in metres (docs/cli.md,
// "Measures").
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/base/number_text.h"
#include "core/measure/contour_lines.h"
#include "core/measure/measure_layers.h"
#include "core/measure/plan_region.h"
#include "core/measure/slope_aspect.h"
#include "core/measure/surface_area.h"
#include "core/measure/volume.h"
#include "db/query/cut_fill.h"
#include "db/query/measure_json.h"
#include "db/query/measure_source.h"

namespace tinbase::cli {

namespace {

// The selection options every single-surface measure takes.
struct SelectionArgs : ReadArgs {
  std::string surface;
  std::string bbox;
  int64_t feature = 0;
  std::string tag;
};

void AddSelectionOptions(CLI::App* cmd, SelectionArgs* args) {
  cmd->add_option("store", args->store, "Store file")->required();
  cmd->add_option("--surface", args->surface, "Surface name")->required();
  cmd->add_option("--bbox", args->bbox, "Only triangles meeting minx,miny,maxx,maxy");
  cmd->add_option("--feature", args->feature, "Only the inside of this polygon feature");
  cmd->add_option("--tag", args->tag, "Only triangles with this tag");
  cmd->add_flag("--json", args->json, "Print JSON");
}

Result<SurfaceFilter> FilterOf(const SelectionArgs& args) {
  SurfaceFilter filter;
  if (!args.bbox.empty()) {
    TB_ASSIGN_OR_RETURN(Box box, ParseBbox(args.bbox));
    filter.bbox = box;
  }
  filter.feature = args.feature;
  if (!args.tag.empty()) filter.tag = args.tag;
  return filter;
}

Result<MeasureSource> Load(Store& store, const SelectionArgs& args) {
  TB_ASSIGN_OR_RETURN(SurfaceFilter filter, FilterOf(args));
  return LoadMeasureSource(store, args.surface, filter);
}

// A number from option `option`: the whole text must be one decimal number of at most 1e15 in
// magnitude (core/base/number_text.h); nan and inf parse, so that the measure can reject them
// by name.
Result<double> ParseNumber(const std::string& option, const std::string& text) {
  const NumberText n = ParseNumberText(text);
  if (n.problem && *n.problem != NumberProblem::kNotFinite)
    return Status::InvalidArgument(option + ": '" + text + "' " +
                                   DescribeNumberProblem(*n.problem));
  return n.value;
}

// Shortest text that reads back as the same double.
std::string Exact(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// --- area --------------------------------------------------------------------------------------

int RunArea(const SelectionArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto source = Load(**store, args);
  if (!source.ok()) return ReportError(source.status());
  const AreaReport report = MeasureArea(source->part.tin, source->frame);
  if (args.json) {
    const nlohmann::json j = AreaJson(*source, report);
    std::cout << j.dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "surface " << source->surface.name << ": " << report.total.triangles
            << " visible triangles, plan area " << Num(report.total.plan) << " m2"
            << (report.geodesic ? " (geodesic)" : "") << ", 3D area " << Num(report.total.surface)
            << " m2\n";
  for (const TagArea& t : report.tags) {
    std::cout << "  " << (t.tag ? "tag " + *t.tag : std::string("no tag")) << ": "
              << t.area.triangles << " triangles, plan " << Num(t.area.plan) << " m2, 3D "
              << Num(t.area.surface) << " m2\n";
  }
  return kExitOk;
}

// --- volume ------------------------------------------------------------------------------------

struct VolumeArgs : SelectionArgs {
  std::string level;
  std::string polygon;
};

int RunVolume(const VolumeArgs& args) {
  auto level = ParseNumber("--level", args.level);
  if (!level.ok()) return ReportError(level.status());
  if (!std::isfinite(*level))
    return ReportError(
        Status::InvalidArgument("--level must be a finite number, got '" + args.level + "'"));
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto source = Load(**store, args);
  if (!source.ok()) return ReportError(source.status());
  std::optional<PlanRegion> region;
  if (!args.polygon.empty()) {
    auto polygons = LoadMeasurePolygons(**store, {source->surface}, 0, args.polygon);
    if (!polygons.ok()) return ReportError(polygons.status());
    auto made = PlanRegion::FromPolygons(*polygons);
    if (!made.ok()) return ReportError(made.status().WithContext(args.polygon));
    region = std::move(*made);
  }
  auto volume =
      VolumeAgainstLevel(source->part.tin, *level, source->frame, region ? &*region : nullptr);
  if (!volume.ok())
    return ReportError(volume.status().WithContext("surface '" + source->surface.name + "'"));
  const SplitMeasure& s = volume->split;
  if (args.json) {
    std::cout << VolumeJson(*source, *level, region.has_value(), *volume).dump(2) << "\n";
    return kExitOk;
  }
  std::cout << "surface " << source->surface.name << " against level " << Num(*level) << ": "
            << Num(s.above_volume) << " m3 above (over " << Num(s.above_area) << " m2), "
            << Num(s.below_volume) << " m3 below (over " << Num(s.below_area) << " m2)\n";
  return kExitOk;
}

// --- cutfill -----------------------------------------------------------------------------------

struct CutFillArgs : ReadArgs {
  CutFillRequest request;
};

int RunCutFill(const CutFillArgs& args) {
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto result = CutFill(**store, args.request);
  if (!result.ok()) return ReportError(result.status());
  const SplitMeasure& s = result->volume.split;
  if (args.json) {
    std::cout << nlohmann::json{{"base", result->base.name},
                                {"top", result->top.name},
                                {"inside_polygon", result->inside_polygon},
                                {"cut_m3", s.below_volume},
                                {"fill_m3", s.above_volume},
                                {"net_m3", s.above_volume - s.below_volume},
                                {"cut_area_m2", s.below_area},
                                {"fill_area_m2", s.above_area},
                                {"plan_area_m2", result->volume.plan_area}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  std::cout << "from " << result->base.name << " to " << result->top.name << " over "
            << Num(result->volume.plan_area) << " m2: cut " << Num(s.below_volume) << " m3, fill "
            << Num(s.above_volume) << " m3, net " << Num(s.above_volume - s.below_volume)
            << " m3\n";
  return kExitOk;
}

// --- slope -------------------------------------------------------------------------------------

struct SlopeArgs : SelectionArgs {
  std::string output;
};

int RunSlope(const SlopeArgs& args) {
  if (!args.output.empty()) {
    if (Status s = LayerFormatForPath(args.output).status(); !s.ok()) return ReportError(s);
  }
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto source = Load(**store, args);
  if (!source.ok()) return ReportError(source.status());
  const Tin& tin = source->part.tin;
  const std::vector<TriangleSlope> slopes = SlopeAndAspect(tin, source->frame, true);
  if (!args.output.empty()) {
    Status s = WriteSlopeLayer(tin, slopes, source->part.triangle_ids,
                               source->crs ? &*source->crs : nullptr, args.output);
    if (!s.ok()) return ReportError(s);
    if (args.json) {
      std::cout << nlohmann::json{{"output", args.output}, {"triangles", slopes.size()}}.dump()
                << "\n";
    } else {
      std::cout << "wrote " << args.output << ": " << slopes.size() << " triangles\n";
    }
    return kExitOk;
  }
  const auto tag_of = [&](uint32_t t) -> std::optional<std::string> {
    const int32_t tag = tin.triangles[t].tag;
    if (tag < 0 || static_cast<size_t>(tag) >= tin.tags.size()) return std::nullopt;
    return tin.tags[static_cast<size_t>(tag)];
  };
  if (!args.json) std::cout << "triangle,slope_deg,aspect_deg,tag\n";
  for (const TriangleSlope& s : slopes) {
    const int64_t id = source->part.triangle_ids[s.triangle];
    if (args.json) {
      std::cout << SlopeJson(*source, s).dump() << "\n";
    } else {
      const std::optional<std::string> tag = tag_of(s.triangle);
      std::cout << id << "," << Exact(s.slope_degrees) << ","
                << (s.aspect_degrees ? Exact(*s.aspect_degrees) : std::string()) << ","
                << (tag ? CsvField(*tag) : std::string()) << "\n";
    }
  }
  return kExitOk;
}

// --- contours ----------------------------------------------------------------------------------

struct ContoursArgs : SelectionArgs {
  std::string interval;
  std::string base = "0";
  std::string output;
};

int RunContours(const ContoursArgs& args) {
  if (Status s = LayerFormatForPath(args.output).status(); !s.ok()) return ReportError(s);
  auto interval = ParseNumber("--interval", args.interval);
  if (!interval.ok()) return ReportError(interval.status());
  auto base = ParseNumber("--base", args.base);
  if (!base.ok()) return ReportError(base.status());
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto source = Load(**store, args);
  if (!source.ok()) return ReportError(source.status());
  ContourOptions options;
  options.interval = *interval;
  options.base = *base;
  auto lines = TraceContours(source->part.tin, options);
  if (!lines.ok())
    return ReportError(lines.status().WithContext("surface '" + source->surface.name + "'"));
  Status s = WriteContourLayer(*lines, source->crs ? &*source->crs : nullptr, args.output);
  if (!s.ok()) return ReportError(s);
  std::set<double> levels;
  size_t closed = 0;
  for (const ContourLine& line : *lines) {
    levels.insert(line.level);
    closed += line.closed ? 1 : 0;
  }
  if (args.json) {
    std::cout << nlohmann::json{{"surface", source->surface.name}, {"output", args.output},
                                {"interval", *interval},           {"base", *base},
                                {"lines", lines->size()},          {"closed", closed},
                                {"levels", levels.size()},         {"min_level", *levels.begin()},
                                {"max_level", *levels.rbegin()}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "wrote " << args.output << ": " << lines->size() << " contour lines (" << closed
              << " closed) at " << levels.size() << " levels from " << Num(*levels.begin())
              << " to " << Num(*levels.rbegin()) << "\n";
  }
  return kExitOk;
}

}  // namespace

void RegisterMeasureCommands(CLI::App& app, int* exit_code) {
  CLI::App* measure = app.add_subcommand(
      "measure", "Areas, volumes, cut and fill, slope and aspect of a surface (in metres)");
  measure->require_subcommand(1);

  auto area_args = std::make_shared<SelectionArgs>();
  CLI::App* area = measure->add_subcommand("area", "Plan and 3D area of the visible part, per tag");
  AddSelectionOptions(area, area_args.get());
  area->callback([=] { *exit_code = RunArea(*area_args); });

  auto volume_args = std::make_shared<VolumeArgs>();
  CLI::App* volume =
      measure->add_subcommand("volume", "Volume of the visible part above and below a level");
  AddSelectionOptions(volume, volume_args.get());
  volume->add_option("--level", volume_args->level, "The level (z in the store's units)")
      ->required();
  volume->add_option("--polygon", volume_args->polygon,
                     "Only inside the polygons of this vector file");
  volume->callback([=] { *exit_code = RunVolume(*volume_args); });

  auto cf_args = std::make_shared<CutFillArgs>();
  CLI::App* cf = measure->add_subcommand(
      "cutfill", "Cut and fill from a base surface (existing ground) to a top one (design)");
  cf->add_option("store", cf_args->store, "Store file")->required();
  cf->add_option("--base", cf_args->request.base, "Base surface (existing ground)")->required();
  cf->add_option("--top", cf_args->request.top, "Top surface (design)")->required();
  cf->add_option("--feature", cf_args->request.feature,
                 "Only inside this polygon feature (of either surface)");
  cf->add_option("--polygon", cf_args->request.polygon_file,
                 "Only inside the polygons of this vector file");
  cf->add_flag("--json", cf_args->json, "Print JSON");
  cf->callback([=] { *exit_code = RunCutFill(*cf_args); });

  auto slope_args = std::make_shared<SlopeArgs>();
  CLI::App* slope = measure->add_subcommand(
      "slope", "Slope and aspect of each visible triangle (CSV, JSON lines or a layer)");
  AddSelectionOptions(slope, slope_args.get());
  slope->add_option("-o,--output", slope_args->output,
                    "Write a layer instead (.gpkg, .geojson, .json, .shp)");
  slope->callback([=] { *exit_code = RunSlope(*slope_args); });

  auto contour_args = std::make_shared<ContoursArgs>();
  CLI::App* contours =
      app.add_subcommand("contours", "Contour lines of a surface as a vector layer");
  AddSelectionOptions(contours, contour_args.get());
  contours->add_option("--interval", contour_args->interval, "Contour interval")->required();
  contours->add_option("--base", contour_args->base, "Levels are base + k * interval (default 0)");
  contours->add_option("-o,--output", contour_args->output, "Output (.gpkg, .geojson, .json, .shp)")
      ->required();
  contours->callback([=] { *exit_code = RunContours(*contour_args); });
}

}  // namespace tinbase::cli
