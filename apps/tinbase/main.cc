// tinbase: the command-line entry point. Only wiring; every command lives in its own file.
#include <gdal_priv.h>

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>

#include "apps/tinbase/command.h"
#include "db/dem_block_cache.h"

namespace tinbase::cli {

int ReportError(const Status& status) {
  std::cerr << "tinbase: " << status.message() << "\n";
  return kExitFailure;
}

namespace {

// TINBASE_DEM_CACHE_MIB sets the memory limit of the process-wide DEM block cache (default
// 256 MiB), like GDAL_CACHEMAX for GDAL: a builder streaming a DEM larger than memory holds at
// most this much of it decoded.
Status ApplyDemCacheLimit() {
  const char* text = std::getenv("TINBASE_DEM_CACHE_MIB");
  if (text == nullptr || *text == '\0') return Status::Ok();
  char* end = nullptr;
  const long long mib = std::strtoll(text, &end, 10);
  if (*end != '\0' || mib < 0 || mib > (int64_t{1} << 30))
    return Status::InvalidArgument(std::string("TINBASE_DEM_CACHE_MIB must be a whole number of "
                                               "MiB (0 or more), got '") +
                                   text + "'");
  DemBlockCache::Instance().SetCapacity(static_cast<size_t>(mib) << 20);
  return Status::Ok();
}

}  // namespace

}  // namespace tinbase::cli

int main(int argc, char** argv) {
  if (tinbase::Status s = tinbase::cli::ApplyDemCacheLimit(); !s.ok())
    return tinbase::cli::ReportError(s);
  GDALAllRegister();
  CPLSetErrorHandler(CPLQuietErrorHandler);  // GDAL's errors reach users through Status messages
  CLI::App app{"tinbase: a store of triangulated terrain and geological surfaces"};
  app.require_subcommand(1);
  app.set_version_flag("--version", TINBASE_VERSION);
  int exit_code = tinbase::cli::kExitOk;
  tinbase::cli::RegisterStoreCommands(app, &exit_code);
  tinbase::cli::RegisterDemCommands(app, &exit_code);
  tinbase::cli::RegisterContourCommand(app, &exit_code);
  tinbase::cli::RegisterTinCommands(app, &exit_code);
  tinbase::cli::RegisterQueryCommands(app, &exit_code);
  tinbase::cli::RegisterExportCommands(app, &exit_code);
  tinbase::cli::RegisterPolygonCommands(app, &exit_code);
  tinbase::cli::RegisterPointsCommands(app, &exit_code);
  tinbase::cli::RegisterDemoCommand(app, &exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return exit_code;
}
