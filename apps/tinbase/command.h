// Command registration for the tinbase CLI: each subcommand is a small kernel.
//
// A kernel registers its CLI11 subcommand (name, one-line description, options) and a handler
// that calls the library and prints the result; no logic lives in main() (PDAL's kernels).
// Handlers return the process exit code. Errors go to stderr as one line: "tinbase: <message>".
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "core/base/status.h"

namespace tinbase::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;

// Prints "tinbase: <status message>" to stderr and returns kExitFailure.
int ReportError(const Status& status);

// Each Register* adds its subcommands to `app`; the handler's exit code is stored in *exit_code.
void RegisterStoreCommands(CLI::App& app, int* exit_code);    // init, info, check
void RegisterDemCommands(CLI::App& app, int* exit_code);      // dem import, dem sample
void RegisterTinCommands(CLI::App& app, int* exit_code);      // tin build
void RegisterQueryCommands(CLI::App& app, int* exit_code);    // locate, neighbours
void RegisterExportCommands(CLI::App& app, int* exit_code);   // export
void RegisterImportCommands(CLI::App& app, int* exit_code);   // import landxml
void RegisterPolygonCommands(CLI::App& app, int* exit_code);  // polygon add
void RegisterPointsCommands(CLI::App& app, int* exit_code);   // points import, add, remove
void RegisterDemoCommand(CLI::App& app, int* exit_code);      // demo
void RegisterMeasureCommands(CLI::App& app, int* exit_code);  // measure area|volume|..., contours
void RegisterTilesCommands(CLI::App& app, int* exit_code);    // tiles build, export, info
void RegisterServeCommand(CLI::App& app, int* exit_code);     // serve
void RegisterHistoryCommands(CLI::App& app, int* exit_code);  // revert, history
// dem from-contours. REQUIRES: RegisterDemCommands ran first (it adds to the `dem` command).
void RegisterContourCommand(CLI::App& app, int* exit_code);

}  // namespace tinbase::cli
