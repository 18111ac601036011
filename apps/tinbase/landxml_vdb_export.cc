#include "apps/tinbase/landxml_vdb_export.h"

#include <iostream>

#include "apps/tinbase/command.h"
#include "apps/tinbase/output.h"
#include "core/base/output_file.h"
#include "core/export/vdb_writer.h"
#include "db/export/landxml_export.h"
#include "db/query/surface_selection.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase::cli {

namespace {

bool Selects(const SurfaceFilter& filter) {
  return filter.bbox || filter.feature != 0 || filter.visible_only || filter.tag;
}

Result<LandXmlSurface> LandXmlOf(Store& store, const LandXmlVdbExportArgs& args) {
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, SurfaceStore(store).Find(args.surface));
  return LoadLandXmlSelection(store, surface, args.filter);
}

Result<Tin> SelectedTin(Store& store, const std::string& name, const SurfaceFilter& filter) {
  SurfaceStore surfaces(store);
  TB_ASSIGN_OR_RETURN(SurfaceInfo surface, surfaces.Find(name));
  if (!Selects(filter)) {
    TB_ASSIGN_OR_RETURN(LoadedSurface loaded, surfaces.Load(surface));
    return std::move(loaded.tin);
  }
  TB_ASSIGN_OR_RETURN(LoadedSurface loaded, SelectSurface(store, surface, filter));
  return std::move(loaded.tin);
}

Result<VdbReport> WriteVdb(Store& store, const LandXmlVdbExportArgs& args) {
  VdbOptions options;
  options.voxel = args.voxel;
  options.floor = args.floor;
  TB_ASSIGN_OR_RETURN(std::optional<Crs> crs, store.GetCrs());
  if (crs) options.crs_wkt = crs->Wkt();
  const SurfaceFilter& filter = args.filter;
  TB_ASSIGN_OR_RETURN(Tin top, SelectedTin(store, args.surface, filter));
  TB_ASSIGN_OR_RETURN(OutputFile file, OutputFile::Create(args.output));
  Result<VdbReport> report = Status::Ok();
  if (args.base.empty()) {
    report = WriteSurfaceLevelSet(top, options, file.temp_path());
  } else {
    if (args.floor) return Status::InvalidArgument("--floor is for a level set, not with --base");
    TB_ASSIGN_OR_RETURN(Tin base, SelectedTin(store, args.base, filter));
    report = WriteThicknessFogVolume(top, base, options, file.temp_path());
  }
  if (!report.ok()) return report.status();
  TB_RETURN_IF_ERROR(file.Commit());
  return report;
}

}  // namespace

int RunLandXmlExport(const LandXmlVdbExportArgs& args) {
  if (args.surface.empty())
    return ReportError(Status::InvalidArgument("--format landxml needs --surface"));
  Stopwatch watch;
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto surface = LandXmlOf(**store, args);
  if (!surface.ok()) return ReportError(surface.status());
  if (Status s = ExportLandXml(*surface, args.output); !s.ok()) return ReportError(s);
  std::cout << "wrote " << args.output << ": " << surface->tin.vertices.size() << " vertices, "
            << surface->tin.triangles.size() << " triangles, " << surface->features.size()
            << " features in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

int RunVdbExport(const LandXmlVdbExportArgs& args) {
  if (args.surface.empty())
    return ReportError(Status::InvalidArgument("--format vdb needs --surface"));
  Stopwatch watch;
  auto store = Store::Open(args.store, Store::Access::kReadOnly);
  if (!store.ok()) return ReportError(store.status());
  auto report = WriteVdb(**store, args);
  if (!report.ok()) return ReportError(report.status());
  std::cout << "wrote " << args.output << ": " << report->grid_class << ", voxel "
            << Num(report->voxel) << ", " << report->active_voxels << " active voxels, volume "
            << Num(report->volume) << " in " << Num(watch.Seconds(), 3) << " s\n";
  return kExitOk;
}

}  // namespace tinbase::cli
