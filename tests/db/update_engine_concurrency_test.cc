// Atomicity and isolation of the update engine against real processes and threads:
//   - a child process inserting polygons is killed with SIGKILL at random moments, many times;
//     the store always checks clean (all eight invariants) and holds whole inserts only;
//   - a reader thread and a reader process locate points while polygons are inserted; every
//     answer equals the answer before the insert or the one after it (never a half state).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "db/dem_store.h"
#include "db/point_locator.h"
#include "db/polygon_editor.h"
#include "db/surface_builder.h"
#include "db/surface_store.h"
#include "tests/support/polygon_files.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::Ngon;
using testing::TempDir;
using testing::WritePolygons;

constexpr double kCx = 539300, kCy = 7497340, kCell = 344.404386931320971;

class UpdateEngineConcurrencyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = testing::StoreTarget(dir_, "s.tinbase");
    auto store = Store::Create(path_, "");
    ASSERT_TRUE(store.ok());
    DemStore dems(**store);
    ASSERT_TRUE(dems.Import({testing::DataPath("geology/hamersley/dtm_rp.tif")}, {}).ok());
    SurfaceBuildOptions o;
    o.surface = "terrain";
    o.greedy.tolerance = 5;
    ASSERT_TRUE(BuildSurfaceFromDem(**store, o).ok());
    for (int k = 0; k < 6; ++k)
      files_.push_back(WritePolygons(dir_, "p" + std::to_string(k) + ".geojson",
                                     {{Ngon(kCx + (k - 3) * 3 * kCell, kCy + (k % 2) * 4 * kCell,
                                            6 * kCell, 20 + k, 0.1 * k)}}));
  }

  static PolygonAddOptions Fill(const std::string& file) {
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = file;
    o.mode = FeatureMode::kFill;
    o.tag_field = "unit";
    return o;
  }

  TempDir dir_;
  std::string path_;
  std::vector<std::string> files_;
};

TEST_F(UpdateEngineConcurrencyTest, KillNineMidInsertLeavesWholeInsertsOnly) {
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay_ms(5, 250);
  int killed_mid_way = 0;
  for (int round = 0; round < 12; ++round) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      auto store = Store::Open(path_);
      if (!store.ok()) _exit(2);
      for (int k = 0;; k = (k + 1) % static_cast<int>(files_.size()))
        if (!AddPolygons(**store, Fill(files_[k])).ok()) _exit(3);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms(rng)));
    ASSERT_EQ(kill(child, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    killed_mid_way += WIFSIGNALED(status);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the inserting child stopped by itself: " << status;

    auto store = Store::Open(path_);
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    testing::ExpectStoreIntact(**store, /*full=*/true);
    // Whole inserts only: one changes row per feature, and every feature has its constraints.
    auto features = (*store)->db().QueryInt("SELECT count(*) FROM features");
    auto changes =
        (*store)->db().QueryInt("SELECT count(*) FROM changes WHERE action = 'polygon add'");
    auto bare = (*store)->db().QueryInt(
        "SELECT count(*) FROM features f WHERE NOT EXISTS "
        "(SELECT 1 FROM constraints c WHERE c.feature = f.id)");
    ASSERT_TRUE(features.ok() && changes.ok() && bare.ok());
    EXPECT_EQ(*features, *changes) << "round " << round;
    EXPECT_EQ(*bare, 0) << "round " << round;
    if (HasFailure()) break;
  }
  EXPECT_EQ(killed_mid_way, 12);
}

// One located answer, comparable across states.
struct Answer {
  double z = 0;
  bool visible = true;
  std::optional<std::string> tag;
  bool Same(const Answer& o) const {
    return std::fabs(z - o.z) <= 1e-6 && visible == o.visible && tag == o.tag;
  }
};

std::vector<std::pair<double, double>> SamplePoints() {
  std::vector<std::pair<double, double>> points;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-8 * kCell, 8 * kCell);
  for (int k = 0; k < 60; ++k) points.push_back({kCx + d(rng), kCy + d(rng)});
  return points;
}

Result<std::vector<Answer>> LocateAll(Store& store, const SurfaceInfo& surface,
                                      const std::vector<std::pair<double, double>>& points) {
  std::vector<Answer> answers;
  for (const auto& [x, y] : points) {
    TB_ASSIGN_OR_RETURN(Location where, LocatePoint(store, surface, x, y));
    answers.push_back({where.z, where.visible, where.tag});
  }
  return answers;
}

TEST_F(UpdateEngineConcurrencyTest, ReadersSeeTheStateBeforeOrAfterEachInsert) {
  const auto points = SamplePoints();
  std::vector<std::vector<Answer>> states;  // states[k]: after k inserts
  auto writer = Store::Open(path_);
  ASSERT_TRUE(writer.ok());
  auto surface = SurfaceStore(**writer).Find("terrain");
  ASSERT_TRUE(surface.ok());
  auto first = LocateAll(**writer, *surface, points);
  ASSERT_TRUE(first.ok());
  states.push_back(*first);

  // The reader process writes "state-free" answers, one line per point: index z visible tag.
  const std::string log = dir_.Path("reader.txt");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    auto store = Store::Open(path_, Store::Access::kReadOnly);
    if (!store.ok()) _exit(2);
    std::ofstream out(log);
    out.precision(17);
    for (int pass = 0; pass < 400; ++pass) {
      for (size_t i = 0; i < points.size(); ++i) {
        auto where = LocatePoint(**store, *surface, points[i].first, points[i].second);
        if (!where.ok()) _exit(3);
        out << i << " " << where->z << " " << where->visible << " " << where->tag.value_or("-")
            << "\n";
      }
    }
    out.close();
    _exit(0);
  }

  std::atomic<bool> done{false};
  std::vector<std::pair<size_t, Answer>> seen;
  std::string reader_error;
  std::thread reader([&] {
    auto store = Store::Open(path_, Store::Access::kReadOnly);
    if (!store.ok()) {
      reader_error = store.status().ToString();
      return;
    }
    while (!done) {
      for (size_t i = 0; i < points.size(); ++i) {
        auto where = LocatePoint(**store, *surface, points[i].first, points[i].second);
        if (!where.ok()) {
          reader_error = where.status().ToString();
          return;
        }
        seen.push_back({i, {where->z, where->visible, where->tag}});
      }
    }
  });
  for (const std::string& file : files_) {
    auto added = AddPolygons(**writer, Fill(file));
    ASSERT_TRUE(added.ok()) << added.status().ToString();
    auto after = LocateAll(**writer, *surface, points);
    ASSERT_TRUE(after.ok());
    states.push_back(*after);
  }
  done = true;
  reader.join();
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  ASSERT_EQ(reader_error, "");

  const auto in_some_state = [&](size_t i, const Answer& a) {
    for (const auto& state : states)
      if (state[i].Same(a)) return true;
    return false;
  };
  for (const auto& [i, a] : seen) ASSERT_TRUE(in_some_state(i, a)) << "thread, point " << i;
  std::ifstream in(log);
  size_t i = 0, lines = 0;
  Answer a;
  int visible = 0;
  std::string tag;
  while (in >> i >> a.z >> visible >> tag) {
    a.visible = visible != 0;
    a.tag = tag == "-" ? std::nullopt : std::optional<std::string>(tag);
    ASSERT_TRUE(in_some_state(i, a)) << "process, point " << i;
    ++lines;
  }
  EXPECT_EQ(lines, 400 * points.size());
  EXPECT_GT(seen.size(), 0u);
}

}  // namespace
}  // namespace tinbase
