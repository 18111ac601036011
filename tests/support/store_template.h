// Stores that many tests start from, made once and copied for each test. A recipe names the
// commands that make such a store (init, dem import, tin build ... through the CLI);
// CopyRecipeStore gives a test a private, exact copy (CopyStore) of the store the recipe made, on
// SQLite and on PostgreSQL alike. CTest runs each test case in a process of its own, so a store
// kept in a static would be made again by every case: the template is shared instead by every test
// process of one ctest run (their parent process), in a folder of that run, made under a file lock
// by the first case that needs it. A test binary run outside ctest makes its own, once per process.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {

// How to make a shared store. The name is the template's key within a ctest run, which every
// test binary shares: one name, one recipe (so recipes used by more than one file live here, and
// a file's own recipe is named after the file).
struct StoreRecipe {
  std::string name;
  // Makes the store at `store` (a target from StoreTarget, nothing there yet); `scratch` holds
  // any input files it writes.
  std::function<void(const std::string& store, const TempDir& scratch)> make;
};

namespace internal {

// The start time of process `pid` (field 22 of /proc/pid/stat), "" when there is no such
// process: with the id, it names one process even after ids wrap around.
inline std::string ProcessStartTime(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t name_end = stat.rfind(')');  // the command name may hold spaces
  if (name_end == std::string::npos) return "";
  std::istringstream fields(stat.substr(name_end + 2));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k) {
  }
  return field;
}

// True when process `pid` runs ctest.
inline bool IsCtest(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/comm");
  std::string comm;
  std::getline(in, comm);
  return comm == "ctest";
}

// Removes the template folders of ctest runs that have ended.
inline void RemoveEndedRunFolders(const std::filesystem::path& base) {
  const std::string prefix = "tinbase-templates-";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string run = name.substr(prefix.size());
    const size_t dash = run.find('-');
    if (dash == std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::strtol(run.substr(0, dash).c_str(), nullptr, 10));
    if (ProcessStartTime(pid) != run.substr(dash + 1))
      std::filesystem::remove_all(entry.path(), ec);
  }
}

// The folder of this ctest run's templates (made on first use); outside ctest, a folder of this
// process.
inline std::string TemplateFolder() {
  static const std::string folder = [] {
    const pid_t parent = getppid();
    if (!IsCtest(parent)) {
      static const TempDir own;  // removed when the process exits
      return own.dir();
    }
    const auto base = std::filesystem::temp_directory_path();
    RemoveEndedRunFolders(base);
    const auto run =
        base / ("tinbase-templates-" + std::to_string(parent) + "-" + ProcessStartTime(parent));
    std::error_code ec;
    std::filesystem::create_directories(run, ec);
    EXPECT_FALSE(ec) << run << ": " << ec.message();
    return run.string();
  }();
  return folder;
}

// An exclusive lock on a file, held while the object lives.
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(open(path.c_str(), O_CREAT | O_RDWR, 0600)) {
    EXPECT_GE(fd_, 0) << "cannot open the lock " << path;
    if (fd_ >= 0) {
      EXPECT_EQ(flock(fd_, LOCK_EX), 0) << "cannot lock " << path;
    }
  }
  ~FileLock() {
    if (fd_ >= 0) close(fd_);  // closing releases the lock
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// The target of `recipe`'s template on this test's backend, made by the first caller of the run.
inline std::string RecipeTemplate(const StoreRecipe& recipe) {
  const std::string folder = TemplateFolder();
  const std::string key = folder + "/" + recipe.name + (OnPostgres() ? ".postgresql" : ".sqlite");
  FileLock lock(key + ".lock");
  // The marker names the finished template; a failed attempt leaves none, so the next test
  // tries again (and fails the same way, saying why).
  std::ifstream marker(key);
  std::string target;
  if (std::getline(marker, target) && !target.empty()) return target;
  static int attempts = 0;  // a new target for each attempt: a failed one may have left a store
  target = OnPostgres() ? FreshPostgresStore("tpl")
                        : folder + "/" + recipe.name + "-" + std::to_string(getpid()) + "-" +
                              std::to_string(attempts++) + ".tinbase";
  const TempDir scratch;
  const bool failed_before = ::testing::Test::HasFailure();
  recipe.make(target, scratch);
  if (!failed_before && ::testing::Test::HasFailure()) return target;
  std::ofstream(key + ".tmp") << target << "\n";
  std::filesystem::rename(key + ".tmp", key);
  return target;
}

}  // namespace internal

// Makes `path` (a target from StoreTarget, no store there yet) a copy of the store `recipe`
// makes. A recipe that failed fails the caller fatally (callers that go on wrap this in
// ASSERT_NO_FATAL_FAILURE), so that no test runs on half a store.
inline void CopyRecipeStore(const StoreRecipe& recipe, const std::string& path) {
  const bool failed_before = ::testing::Test::HasFailure();
  const std::string made = internal::RecipeTemplate(recipe);
  ASSERT_TRUE(failed_before || !::testing::Test::HasFailure())
      << "making the shared store '" << recipe.name << "' failed (above)";
  CopyStore(made, path);
}

// init, then `dem import` of `dem` (a path under tests/data) with `import_options`.
inline void MakeDemStore(const std::string& store, const std::string& dem,
                         const std::string& import_options = "") {
  RunWrite(store, "init " + Quote(store));
  RunWrite(store, "dem import " + Quote(store) + " " + Quote(DataPath(dem)) + import_options);
}

// The Hamersley DEM (EPSG:28350) imported.
inline const StoreRecipe& HamersleyDemRecipe() {
  static const StoreRecipe recipe{"hamersley-dem", [](const std::string& store, const TempDir&) {
                                    MakeDemStore(store, "geology/hamersley/dtm_rp.tif");
                                  }};
  return recipe;
}

// The Hamersley DEM and the surface "terrain" built on it (greedy) with `tolerance` metres.
inline const StoreRecipe& HamersleyTerrainRecipe(int tolerance) {
  static std::map<int, StoreRecipe> recipes;
  auto [it, fresh] = recipes.try_emplace(tolerance);
  if (fresh) {
    it->second = {"hamersley-terrain-" + std::to_string(tolerance),
                  [tolerance](const std::string& store, const TempDir&) {
                    MakeDemStore(store, "geology/hamersley/dtm_rp.tif");
                    RunWrite(store, "tin build " + Quote(store) +
                                        " --surface terrain --tolerance " +
                                        std::to_string(tolerance));
                  }};
  }
  return it->second;
}

// The DEM N43E007 (SRTM, 1201 x 1201) and the surface "t" built on it with tolerance 20 m.
inline const StoreRecipe& DemoRecipe() {
  static const StoreRecipe recipe{
      "n43e007-t-20", [](const std::string& store, const TempDir&) {
        MakeDemStore(store, "dem/N43E007.hgt");
        RunWrite(store, "tin build " + Quote(store) + " --surface t --tolerance 20");
      }};
  return recipe;
}

}  // namespace tinbase::testing
