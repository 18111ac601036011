// Registration points for commands whose kernels are being written; each moves to its own file.
#include "apps/tinbase/command.h"

namespace tinbase::cli {
void RegisterStoreCommands(CLI::App&, int*) {}
void RegisterDemCommands(CLI::App&, int*) {}
void RegisterTinCommands(CLI::App&, int*) {}
void RegisterQueryCommands(CLI::App&, int*) {}
void RegisterExportCommands(CLI::App&, int*) {}
void RegisterPolygonCommands(CLI::App&, int*) {}
void RegisterDemoCommand(CLI::App&, int*) {}
}  // namespace tinbase::cli
