// The crash loop (docs/reliability.md, "kill -9"): writing commands of the CLI killed with
// SIGKILL at random moments, one after another on one store. Each round picks one of the commands
// of tests/stress/crash_commands.h (every command that writes: polygon add, add --each, remove
// and update, points add and remove, revert, tin build, points import of XYZ and of LAS, dem
// import, tiles build and update), starts it, kills it after a random delay up to about its
// usual run time, and then demands:
//   - the full check (every invariant, as `check --full` runs it) passes;
//   - the store holds all or none of each of the command's transactions (ExpectWhole);
//   - a command that finished before the kill exited 0 and did all of its work.
// The test command runs kKills rounds; TINBASE_CRASH_KILLS sets another count (the full run of
// tests/stress/crash_loop.sh is 1000) and TINBASE_CRASH_SEED replays a run. The store starts
// again from its first state every kRoundsPerStore rounds, so the checks stay as cheap. The check
// runs in this process (one store open per round, no second binary's start-up), and the counts
// after a round are the counts before the next one.
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

#include "db/integrity_check.h"
#include "db/store.h"
#include "tests/stress/crash_commands.h"
#include "tests/support/cli_support.h"
#include "tests/support/polygon_files.h"
#include "tests/support/test_support.h"

namespace tinbase::testing {
namespace {

constexpr int kKills = 50;
constexpr int kRoundsPerStore = 20;
// Centre of the Hamersley DEM (EPSG:28350), and its cell size.
constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

// The binary the rounds run: TINBASE_CRASH_CLI when set (a copy, so that a long run is not
// disturbed by a rebuild of the tree's binary), else the tree's.
const char* Cli() {
  const char* cli = std::getenv("TINBASE_CRASH_CLI");
  return cli != nullptr ? cli : TINBASE_CLI;
}

// Runs `args` (split on spaces; no argument holds one) as a child; returns its pid.
pid_t Start(const std::string& args) {
  std::vector<std::string> words = {Cli(), "--quiet"};
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
    execv(Cli(), argv.data());
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

// Seconds a run spent in each part of its rounds, to see where a kill cycle's time goes.
struct Spent {
  double reset = 0, command = 0, check = 0;
};

class CrashLoop {
 public:
  CrashLoop(const TempDir& dir, uint32_t seed) : dir_(dir), random_(seed) {
    base_ = dir.Path("base.tinbase");
    store_ = dir.Path("s.tinbase");
    for (const std::string& args :
         {"init " + base_ + " --crs EPSG:28350",
          "dem import " + base_ + " " + DataPath("geology/hamersley/dtm_rp.tif"),
          "tin build " + base_ + " --surface terrain --tolerance 20"}) {
      const Outcome setup = RunAndKill(args, std::chrono::hours(1));
      EXPECT_TRUE(!setup.killed && setup.exit_code == 0) << args;
    }
    WritePoints();
    for (double& s : usual_seconds_) s = -1;
  }

  // One round; returns false after a failure.
  bool Round(int round) {
    auto at = std::chrono::steady_clock::now();
    const auto lap = [&at](double& into) {
      const auto now = std::chrono::steady_clock::now();
      into += std::chrono::duration<double>(now - at).count();
      at = now;
    };
    if (round % kRoundsPerStore == 0) {
      Reset();
      if (!Check(&counts_)) return false;
    }
    const Counts before = counts_;
    const Command command = Pick(before);
    const std::string args = Args(command, round, before);
    lap(spent_.reset);
    // The first run of each command goes unkilled, to learn how long it takes here; later ones
    // are killed at a uniform moment of up to 1.2 times the last time one took.
    const double usual = usual_seconds_[static_cast<int>(command)];
    const double delay_seconds =
        usual < 0 ? 3600 : std::uniform_real_distribution<double>(0, 1.2 * usual)(random_);
    const auto delay = std::chrono::microseconds(static_cast<int64_t>(delay_seconds * 1e6));
    const Outcome outcome = RunAndKill(args, delay);
    lap(spent_.command);
    if (!outcome.killed) {
      usual_seconds_[static_cast<int>(command)] = outcome.seconds;
      ++finished_;
    } else {
      ++killed_;
      ++kills_of_[static_cast<int>(command)];
    }
    std::ostringstream what;
    what << "round " << round << ", " << Name(command)
         << (outcome.killed ? " killed after " : " ended after ") << outcome.seconds << " s";
    SCOPED_TRACE(what.str());
    if (!outcome.killed) {
      EXPECT_EQ(outcome.exit_code, 0) << args;
    }
    Counts after;
    if (Check(&after)) ExpectWhole(command, before, after, !outcome.killed);
    lap(spent_.check);
    if (outcome.killed && (after.changes != before.changes || after.surfaces != before.surfaces ||
                           after.dems != before.dems || !SameTiles(after, before)))
      ++killed_after_a_commit_;
    counts_ = after;
    return !::testing::Test::HasFailure();
  }

  int killed() const { return killed_; }
  int finished() const { return finished_; }
  int killed_after_a_commit() const { return killed_after_a_commit_; }
  int kills_of(Command c) const { return kills_of_[static_cast<int>(c)]; }
  const Spent& spent() const { return spent_; }

 private:
  void Reset() {
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(store_ + suffix);
    std::filesystem::copy_file(base_, store_);
  }

  // Opens the store as `check --full` does (read-only: this open is the one that meets a killed
  // writer's WAL), runs the full check and counts the rows. False after a failure.
  bool Check(Counts* counts) {
    auto store = Store::Open(store_, Store::Access::kReadOnly);
    EXPECT_TRUE(store.ok()) << store.status().ToString();
    if (!store.ok()) return false;
    CheckOptions options;
    options.full = true;
    auto problems = CheckStore(**store, options);
    EXPECT_TRUE(problems.ok()) << problems.status().ToString();
    if (!problems.ok()) return false;
    EXPECT_TRUE(problems->empty())
        << problems->front().message << " and " << problems->size() - 1 << " more";
    *counts = CountRows((*store)->db());
    return problems->empty();
  }

  // A command at random; one that needs something the store lacks becomes the one that makes it.
  Command Pick(const Counts& c) {
    Command command = static_cast<Command>(random_() % static_cast<int>(Command::kCount));
    if ((command == Command::kRemove || command == Command::kUpdate) && c.max_polygon == 0)
      return Command::kAdd;
    if (command == Command::kRevert && c.last_edit_tx == 0) return Command::kAdd;
    if (command == Command::kPointsRemove && c.max_points == 0) return Command::kPointsAdd;
    if (command == Command::kTilesUpdate && c.pyramid_tx < 0) return Command::kTilesBuild;
    return command;
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

  // Three survey points at random places of the DEM's middle, within its relief there.
  std::string SurveyPoints() {
    std::uniform_real_distribution<double> offset(-40 * kCell, 40 * kCell);
    std::uniform_real_distribution<double> z(480, 620);
    const std::string path = dir_.Path("shots.xyz");
    std::ofstream out(path);
    out.precision(17);
    for (int k = 0; k < 3; ++k)
      out << kCx + offset(random_) << " " << kCy + offset(random_) << " " << z(random_) << "\n";
    return path;
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
        return "polygon remove " + store_ + " " + std::to_string(before.max_polygon);
      case Command::kUpdate:
        return "polygon update " + store_ + " " + std::to_string(before.max_polygon) + " " +
               Polygons(1);
      case Command::kPointsAdd:
        return "points add " + store_ + " " + SurveyPoints() + " --surface terrain";
      case Command::kPointsRemove:
        return "points remove " + store_ + " --feature " + std::to_string(before.max_points);
      case Command::kRevert:
        return "revert " + store_ + " " + std::to_string(before.last_edit_tx);
      case Command::kBuild:
        return "tin build " + store_ + " --surface b" + n + " --dem dtm_rp --tolerance 40";
      case Command::kPoints:
        return "points import " + store_ + " " + dir_.Path("points.xyz") + " --surface p" + n;
      case Command::kLas:
        return "points import " + store_ + " " + DataPath("las/mvk-thin.las") + " --surface l" + n;
      case Command::kDem:
        return "dem import " + store_ + " " + DataPath("geology/hamersley/dtm_rp.tif") +
               " --name d" + n;
      case Command::kTilesBuild:
        return "tiles build " + store_ + " --surface terrain --max-zoom 7";
      case Command::kTilesUpdate:
        return "tiles update " + store_ + " --surface terrain";
      case Command::kCount:
        break;
    }
    return "";
  }

  const TempDir& dir_;
  std::mt19937 random_;
  std::string base_, store_;
  Counts counts_;
  double usual_seconds_[static_cast<int>(Command::kCount)];
  int kills_of_[static_cast<int>(Command::kCount)] = {};
  int killed_ = 0, finished_ = 0, killed_after_a_commit_ = 0;
  Spent spent_;
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
            << "\nkills per command:";
  for (int c = 0; c < static_cast<int>(Command::kCount); ++c)
    std::cout << (c == 0 ? " " : ", ") << Name(static_cast<Command>(c)) << " "
              << loop.kills_of(static_cast<Command>(c));
  const Spent& spent = loop.spent();
  std::cout << "\nseconds in picking and resetting: " << spent.reset
            << ", in the commands (to their kill or end): " << spent.command
            << ", in the check and counts: " << spent.check << "\n";
  EXPECT_GE(loop.killed(), wanted);
}

}  // namespace
}  // namespace tinbase::testing
