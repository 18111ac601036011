// The crash loop (docs/reliability.md, "kill -9"): writing commands of the CLI killed with
// SIGKILL at random moments, one after another on one store. Each round picks a command (polygon
// add, add --each, remove and update, tin build, points import, dem import), starts it, kills it
// after a random delay up to about its usual run time, and then demands:
//   - `check --full` passes;
//   - the store holds all or none of each of the command's transactions: the change log and the
//     rows the command writes (features, surfaces, DEMs) moved together, by whole transactions;
//   - a command that finished before the kill exited 0 and did all of its work.
// The test command runs kKills rounds; TINBASE_CRASH_KILLS sets another count (the full run of
// tests/stress/crash_loop.sh is 1000) and TINBASE_CRASH_SEED replays a run. The store starts
// again from its first state every kRoundsPerStore rounds, so the checks stay as cheap.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

constexpr int kKills = 50;
constexpr int kRoundsPerStore = 25;
// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

enum class Command { kAdd, kAddEach, kRemove, kUpdate, kBuild, kPoints, kDem, kCount };

const char* Name(Command c) {
  static const char* names[] = {"polygon add",    "polygon add --each", "polygon remove",
                                "polygon update", "tin build",          "points import",
                                "dem import"};
  return names[static_cast<int>(c)];
}

// The rows a command's transactions write, counted.
struct Counts {
  int64_t changes = 0, features = 0, surfaces = 0, dems = 0, max_feature = 0;
};

Counts CountRows(const std::string& store) {
  Counts c;
  auto opened = Store::Open(store, Store::Access::kReadOnly);
  EXPECT_TRUE(opened.ok()) << opened.status().ToString();
  if (!opened.ok()) return c;
  Connection& db = (*opened)->db();
  auto count = [&db](const char* sql) {
    auto n = db.QueryInt(sql);
    EXPECT_TRUE(n.ok()) << sql << ": " << n.status().ToString();
    return n.ok() ? *n : -1;
  };
  c.changes = count("SELECT count(*) FROM changes");
  c.features = count("SELECT count(*) FROM features");
  c.surfaces = count("SELECT count(*) FROM surfaces");
  c.dems = count("SELECT count(*) FROM dems");
  c.max_feature = count("SELECT coalesce(max(id), 0) FROM features");
  return c;
}

// Runs `args` (split on spaces; no argument holds one) as a child; returns its pid.
pid_t Start(const std::string& args) {
  std::vector<std::string> words = {TINBASE_CLI, "--quiet"};
  size_t at = 0;
  while (at < args.size()) {
    const size_t space = std::min(args.find(' ', at), args.size());
    if (space > at) words.push_back(args.substr(at, space - at));
    at = space + 1;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    // dup2, not freopen: the child must not flush the parent's buffered output a second time.
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execv(TINBASE_CLI, argv.data());
    _exit(127);
  }
  return pid;
}

struct Outcome {
  bool killed = false;  // else it exited first
  int exit_code = 0;
  double seconds = 0;
};

// Starts `args`, kills it after `delay` unless it ended before.
Outcome RunAndKill(const std::string& args, std::chrono::microseconds delay) {
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = Start(args);
  Outcome outcome;
  int status = 0;
  const auto deadline = start + delay;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      outcome.seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return outcome;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.killed = WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL;
  if (!outcome.killed) outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

class CrashLoop {
 public:
  CrashLoop(const TempDir& dir, uint32_t seed) : dir_(dir), random_(seed) {
    base_ = dir.Path("base.tinbase");
    store_ = dir.Path("s.tinbase");
    RunWrite(base_, "init " + base_ + " --crs EPSG:28350");
    RunWrite(base_, "dem import " + base_ + " " + DataPath("geology/hamersley/dtm_rp.tif"));
    RunWrite(base_, "tin build " + base_ + " --surface terrain --tolerance 10");
    WritePoints();
    for (double& s : usual_seconds_) s = -1;
  }

  // One round; returns false after a failure.
  bool Round(int round) {
    if (round % kRoundsPerStore == 0) Reset();
    const Counts before = CountRows(store_);
    Command command = static_cast<Command>(random_() % static_cast<int>(Command::kCount));
    if ((command == Command::kRemove || command == Command::kUpdate) && before.features == 0)
      command = Command::kAdd;
    const std::string args = Args(command, round, before);
    // The first run of each command goes unkilled, to learn how long it takes here; later ones
    // are killed at a uniform moment of up to 1.2 times the last time one took.
    const double usual = usual_seconds_[static_cast<int>(command)];
    const double delay_seconds =
        usual < 0 ? 3600 : std::uniform_real_distribution<double>(0, 1.2 * usual)(random_);
    const auto delay = std::chrono::microseconds(static_cast<int64_t>(delay_seconds * 1e6));
    const Outcome outcome = RunAndKill(args, delay);
    if (!outcome.killed) {
      usual_seconds_[static_cast<int>(command)] = outcome.seconds;
      ++finished_;
    } else {
      ++killed_;
    }
    std::ostringstream what;
    what << "round " << round << ", " << Name(command)
         << (outcome.killed ? " killed after " : " ended after ") << outcome.seconds << " s";
    SCOPED_TRACE(what.str());
    if (!outcome.killed) {
      EXPECT_EQ(outcome.exit_code, 0) << args;
    }
    const CliResult check = RunCli("check --full " + Quote(store_));
    EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
    const Counts after = CountRows(store_);
    ExpectWhole(command, before, after, !outcome.killed);
    if (outcome.killed && (after.changes != before.changes || after.surfaces != before.surfaces ||
                           after.dems != before.dems))
      ++killed_after_a_commit_;
    return !::testing::Test::HasFailure();
  }

  int killed() const { return killed_; }
  int finished() const { return finished_; }
  int killed_after_a_commit() const { return killed_after_a_commit_; }

 private:
  void Reset() {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(store_ + suffix);
    std::filesystem::copy_file(base_, store_);
  }

  void WritePoints() {
    std::ofstream out(dir_.Path("points.xyz"));
    out.precision(17);
    for (int i = 0; i < 60; ++i)
      for (int j = 0; j < 60; ++j)
        out << kCx + i * 97.3 + (j % 3) << " " << kCy + j * 101.9 + (i % 5) << " "
            << 500 + ((i * 7 + j * 13) % 29) << "\n";
  }

  // Polygons at random places of the DEM's middle.
  std::string Polygons(int count) {
    std::uniform_real_distribution<double> offset(-40 * kCell, 40 * kCell);
    std::uniform_real_distribution<double> radius(2 * kCell, 6 * kCell);
    std::vector<std::vector<PointList>> polygons;
    for (int k = 0; k < count; ++k)
      polygons.push_back({Ngon(kCx + offset(random_), kCy + offset(random_), radius(random_),
                               8 + static_cast<int>(random_() % 12))});
    return WritePolygons(dir_, count == 1 ? "one.geojson" : "some.geojson", polygons);
  }

  std::string Args(Command command, int round, const Counts& before) {
    const std::string n = std::to_string(round);
    switch (command) {
      case Command::kAdd:
        return "polygon add " + store_ + " " + Polygons(1) + " --surface terrain --mode fill";
      case Command::kAddEach:
        return "polygon add " + store_ + " " + Polygons(3) +
               " --surface terrain --mode fill --tag-field unit --each";
      case Command::kRemove:
        return "polygon remove " + store_ + " " + std::to_string(before.max_feature);
      case Command::kUpdate:
        return "polygon update " + store_ + " " + std::to_string(before.max_feature) + " " +
               Polygons(1);
      case Command::kBuild:
        return "tin build " + store_ + " --surface b" + n + " --dem dtm_rp --tolerance 20";
      case Command::kPoints:
        return "points import " + store_ + " " + dir_.Path("points.xyz") + " --surface p" + n;
      case Command::kDem:
        return "dem import " + store_ + " " + DataPath("geology/hamersley/dtm_rp.tif") +
               " --name d" + n;
      case Command::kCount:
        break;
    }
    return "";
  }

  // All or none of each transaction: what the change log gained, the rows moved by.
  void ExpectWhole(Command command, const Counts& b, const Counts& a, bool finished) {
    const int64_t logged = a.changes - b.changes;
    const int64_t features = a.features - b.features;
    const int64_t surfaces = a.surfaces - b.surfaces;
    const int64_t dems = a.dems - b.dems;
    EXPECT_GE(logged, 0);
    switch (command) {
      case Command::kAdd:
        EXPECT_LE(logged, 1);
        EXPECT_EQ(features, logged);
        if (finished) {
          EXPECT_EQ(logged, 1);
        }
        break;
      case Command::kAddEach:
        EXPECT_LE(logged, 3);
        EXPECT_EQ(features, logged);
        break;
      case Command::kRemove:
        EXPECT_LE(logged, 1);
        EXPECT_EQ(features, -logged);
        if (finished) {
          EXPECT_EQ(logged, 1);
        }
        break;
      case Command::kUpdate:
        EXPECT_LE(logged, 1);
        EXPECT_EQ(features, 0);
        EXPECT_EQ(a.max_feature > b.max_feature, logged == 1);
        if (finished) {
          EXPECT_EQ(logged, 1);
        }
        break;
      case Command::kBuild:
        EXPECT_LE(surfaces, 1);
        EXPECT_GE(surfaces, 0);
        EXPECT_EQ(logged, surfaces);
        if (finished) {
          EXPECT_EQ(surfaces, 1);
        }
        break;
      case Command::kPoints:
        EXPECT_LE(surfaces, 1);
        EXPECT_GE(surfaces, 0);
        EXPECT_EQ(features, 0);
        if (finished) {
          EXPECT_EQ(surfaces, 1);
        }
        break;
      case Command::kDem:
        EXPECT_LE(dems, 1);
        EXPECT_GE(dems, 0);
        EXPECT_EQ(logged, 0);
        if (finished) {
          EXPECT_EQ(dems, 1);
        }
        break;
      case Command::kCount:
        break;
    }
    const bool edits_features = command == Command::kAdd || command == Command::kAddEach ||
                                command == Command::kRemove || command == Command::kUpdate;
    EXPECT_TRUE(edits_features || features == 0) << "features moved by " << features;
  }

  const TempDir& dir_;
  std::mt19937 random_;
  std::string base_, store_;
  double usual_seconds_[static_cast<int>(Command::kCount)];
  int killed_ = 0, finished_ = 0, killed_after_a_commit_ = 0;
};

int KillsWanted() {
  const char* text = std::getenv("TINBASE_CRASH_KILLS");
  return text != nullptr ? std::max(1, std::atoi(text)) : kKills;
}

TEST(CrashLoopTest, KilledWritersLeaveWholeTransactionsAndAStoreThatChecksClean) {
  const char* seed_text = std::getenv("TINBASE_CRASH_SEED");
  const uint32_t seed = seed_text != nullptr
                            ? static_cast<uint32_t>(std::strtoul(seed_text, nullptr, 10))
                            : std::random_device()();
  std::cout << "seed " << seed << " (TINBASE_CRASH_SEED replays it)\n";
  TempDir dir;
  CrashLoop loop(dir, seed);
  ASSERT_FALSE(::testing::Test::HasFailure());
  const int wanted = KillsWanted();
  // Rounds whose command ended before its kill do not count as kills.
  for (int round = 0; loop.killed() < wanted; ++round) {
    if (!loop.Round(round)) break;
    if ((round + 1) % 100 == 0)
      std::cout << round + 1 << " rounds, " << loop.killed() << " kills\n" << std::flush;
  }
  std::cout << "kills: " << loop.killed() << " (" << loop.killed_after_a_commit()
            << " after a commit of the command), commands that ended first: " << loop.finished()
            << "\n";
  EXPECT_GE(loop.killed(), wanted);
}

}  // namespace
}  // namespace tinbase::testing
