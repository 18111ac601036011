// tinbase: the command-line entry point. Only wiring; every command lives in its own file.
#include <gdal_priv.h>

#include <iostream>

#include "apps/tinbase/command.h"

namespace tinbase::cli {

int ReportError(const Status& status) {
  std::cerr << "tinbase: " << status.message() << "\n";
  return kExitFailure;
}

}  // namespace tinbase::cli

int main(int argc, char** argv) {
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
