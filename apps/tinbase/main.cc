// tinbase: the command-line entry point. Only wiring; every command lives in its own file.
#include <gdal_priv.h>
#include <tbb/global_control.h>

#include <cstdint>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <string>

#include "apps/tinbase/command.h"
#include "apps/tinbase/number_options.h"
#include "apps/tinbase/progress.h"
#include "db/dem_block_cache.h"
#include "db/store.h"

namespace tinbase::cli {

int ReportError(const Status& status) {
  // One line, whatever a library put into the message: scripts read the first line.
  std::string line = status.message();
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  std::cerr << "tinbase: " << line << "\n";
  return kExitFailure;
}

namespace {

// A whole number of MiB from the environment variable `name`; nullopt when it is not set.
Result<std::optional<int64_t>> MibFromEnv(const char* name) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return std::optional<int64_t>();
  char* end = nullptr;
  const long long mib = std::strtoll(text, &end, 10);
  if (*end != '\0' || mib < 0 || mib > (int64_t{1} << 30))
    return Status::InvalidArgument(
        std::string(name) + " must be a whole number of MiB (0 or more), got '" + text + "'");
  return std::optional<int64_t>(int64_t{mib} << 20);
}

// A whole number from the environment variable `name`, at least 1; nullopt when it is not set.
Result<std::optional<int>> CountFromEnv(const char* name) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return std::optional<int>();
  char* end = nullptr;
  const long long count = std::strtoll(text, &end, 10);
  if (*end != '\0' || count < 1 || count > 4096)
    return Status::InvalidArgument(
        std::string(name) + " must be a whole number of threads (1 or more), got '" + text + "'");
  return std::optional<int>(static_cast<int>(count));
}

// TINBASE_DEM_CACHE_MIB sets the memory limit of the process-wide DEM block cache (default
// 256 MiB), like GDAL_CACHEMAX for GDAL: a builder streaming a DEM larger than memory holds at
// most this much of it decoded. TINBASE_MMAP_MIB sets how much of a store file is read through a
// memory map (default 1024; 0: none), whose pages count as resident memory.
Status ApplyMemoryLimits() {
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> cache, MibFromEnv("TINBASE_DEM_CACHE_MIB"));
  if (cache) DemBlockCache::Instance().SetCapacity(static_cast<size_t>(*cache));
  TB_ASSIGN_OR_RETURN(std::optional<int64_t> map, MibFromEnv("TINBASE_MMAP_MIB"));
  if (map) Store::SetMemoryMapLimit(*map);
  return Status::Ok();
}

// TINBASE_THREADS caps the threads parallel work uses (TBB's, by default one per core); results
// are the same on any number. The limit lives as long as the returned object.
Result<std::unique_ptr<tbb::global_control>> ApplyThreadLimit() {
  TB_ASSIGN_OR_RETURN(std::optional<int> threads, CountFromEnv("TINBASE_THREADS"));
  if (!threads) return std::unique_ptr<tbb::global_control>();
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               static_cast<size_t>(*threads));
}

}  // namespace

}  // namespace tinbase::cli

int main(int argc, char** argv) {
  if (tinbase::Status s = tinbase::cli::ApplyMemoryLimits(); !s.ok())
    return tinbase::cli::ReportError(s);
  auto thread_limit = tinbase::cli::ApplyThreadLimit();
  if (!thread_limit.ok()) return tinbase::cli::ReportError(thread_limit.status());
  GDALAllRegister();
  CPLSetErrorHandler(CPLQuietErrorHandler);  // GDAL's errors reach users through Status messages
  CLI::App app{"tinbase: a store of triangulated terrain and geological surfaces"};
  app.require_subcommand(1);
  app.set_version_flag("--version", TINBASE_VERSION);
  // Global, before or after the subcommand (fallthrough): long jobs draw no progress bar.
  app.add_flag_callback(
      "-q,--quiet", [] { tinbase::cli::SetQuiet(true); },
      "No progress bars (they are drawn only when stderr is a terminal anyway)");
  app.fallthrough();
  int exit_code = tinbase::cli::kExitOk;
  tinbase::cli::RegisterStoreCommands(app, &exit_code);
  tinbase::cli::RegisterDemCommands(app, &exit_code);
  tinbase::cli::RegisterContourCommand(app, &exit_code);
  tinbase::cli::RegisterTinCommands(app, &exit_code);
  tinbase::cli::RegisterQueryCommands(app, &exit_code);
  tinbase::cli::RegisterExportCommands(app, &exit_code);
  tinbase::cli::RegisterImportCommands(app, &exit_code);
  tinbase::cli::RegisterPolygonCommands(app, &exit_code);
  tinbase::cli::RegisterPointsCommands(app, &exit_code);
  tinbase::cli::RegisterTilesCommands(app, &exit_code);
  tinbase::cli::RegisterDemoCommand(app, &exit_code);
  tinbase::cli::RegisterMeasureCommands(app, &exit_code);
  tinbase::cli::RegisterServeCommand(app, &exit_code);
  tinbase::cli::RegisterHistoryCommands(app, &exit_code);
  tinbase::cli::CheckNumberOptions(app);
  // Bad arguments are reported like every other error: one line that scripts can read.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return std::string("tinbase: ") + e.what() + " (see --help)\n";
  });
  // Handlers return errors as values; anything thrown past them (a library's exception, memory
  // exhausted) still ends as one line and an exit code, never as an abort.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::bad_alloc&) {
    return tinbase::cli::ReportError(
        tinbase::Status::IOError("out of memory (an input larger than this machine can hold?)"));
  } catch (const std::exception& e) {
    return tinbase::cli::ReportError(tinbase::Status::IOError(std::string("failed: ") + e.what()));
  } catch (...) {
    return tinbase::cli::ReportError(tinbase::Status::IOError("failed: unknown exception"));
  }
  return exit_code;
}
