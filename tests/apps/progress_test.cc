// The progress bar (apps/tinbase/progress.h): what it draws on a terminal, how often, and that
// the CLI draws nothing when stderr is not a terminal or --quiet is given.
#include "apps/tinbase/progress.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <sstream>
#include <string>

#include "tests/support/cli_support.h"
#include "tests/support/test_support.h"

namespace tinbase::cli {
namespace {

using testing::DataPath;
using testing::Quote;
using testing::RunCli;
using testing::TempDir;
using Clock = ProgressBar::Clock;

TEST(ProgressLine, ShowsTheBarPercentAndElapsedTime) {
  EXPECT_EQ(ProgressLine("tin build", 0.5, 75.4),
            "tin build [###############---------------]  50 %  1:15");
  EXPECT_EQ(ProgressLine("x", 0, 0), "x [------------------------------]   0 %  0:00");
  EXPECT_EQ(ProgressLine("x", 1, 3600), "x [##############################] 100 %  60:00");
}

TEST(ProgressBar, OnATerminalDrawsInPlaceAtMostFiveTimesASecond) {
  std::ostringstream out;
  ProgressBar bar("job", /*active=*/true, out);
  const Clock::time_point t0 = Clock::now();
  bar.Update(0.25, t0);
  EXPECT_EQ(out.str(), "\rjob [#######-----------------------]  25 %  0:00");
  bar.Update(0.5, t0 + std::chrono::milliseconds(50));  // too soon: not drawn
  EXPECT_EQ(out.str().find("50 %"), std::string::npos);
  bar.Update(0.6, t0 + std::chrono::milliseconds(300));
  EXPECT_NE(out.str().find("\rjob [##################------------]  60 %"), std::string::npos);
  bar.Update(0.4, t0 + std::chrono::seconds(1));  // never backwards
  EXPECT_EQ(out.str().find("40 %"), std::string::npos);
  bar.Finish();
  const std::string all = out.str();
  EXPECT_NE(all.find("\rjob [##############################] 100 %"), std::string::npos);
  EXPECT_EQ(all.back(), '\n');
  bar.Update(0.9);  // after Finish: nothing
  EXPECT_EQ(out.str(), all);
}

TEST(ProgressBar, ACallbackDrawsAndAnUnfinishedBarEndsItsLine) {
  std::ostringstream out;
  {
    ProgressBar bar("job", true, out);
    const std::function<void(double)> progress = bar.Callback();
    ASSERT_TRUE(progress);
    progress(0.1);
    EXPECT_NE(out.str().find("10 %"), std::string::npos);
  }  // a failed job: the error message must start a line of its own
  EXPECT_EQ(out.str().back(), '\n');
}

TEST(ProgressBar, OffATerminalDrawsNothing) {
  std::ostringstream out;
  ProgressBar bar("job", /*active=*/false, out);
  EXPECT_FALSE(bar.Callback());  // library calls skip an empty callback
  bar.Update(0.5);
  bar.Finish();
  EXPECT_EQ(out.str(), "");
}

// Whether `text` holds any piece of a bar.
bool HasBar(const std::string& text) {
  return text.find(" %  ") != std::string::npos || text.find("[#") != std::string::npos ||
         text.find("[-") != std::string::npos;
}

// A store with the Hamersley DEM, plus the commands that take a progress bar, each run as
// `tinbase <command>` with `prefix` before the command.
std::vector<std::string> LongCommands(const TempDir& dir, const std::string& name,
                                      const std::string& prefix) {
  const std::string store = Quote(dir.Path(name + ".tinbase"));
  const std::string points = Quote(dir.Path(name + "_points.tinbase"));
  return {prefix + "init " + store,
          prefix + "dem import " + store + " " + Quote(DataPath("geology/hamersley/dtm_rp.tif")),
          prefix + "tin build " + store + " --surface terrain --tolerance 5",
          prefix + "polygon add " + store + " " +
              Quote(DataPath("geology/hamersley/geology.geojson")) +
              " --surface terrain --mode fill --tag-field unitname --each",
          prefix + "init " + points,
          prefix + "points import " + points + " " + Quote(DataPath("las/autzen_trim.las")) +
              " --surface ground"};
}

TEST(ProgressCli, NoProgressWhenStderrIsNotATerminal) {
  TempDir dir;
  for (const std::string& prefix : {std::string(), std::string("--quiet ")}) {
    for (const std::string& command : LongCommands(dir, prefix.empty() ? "a" : "b", prefix)) {
      const auto r = RunCli(command);
      ASSERT_EQ(r.exit_code, 0) << command << ": " << r.err;
      EXPECT_FALSE(HasBar(r.err)) << command << ": " << r.err;
      EXPECT_EQ(r.err.find('\r'), std::string::npos) << command << ": " << r.err;
    }
  }
}

// The command run on a pseudo-terminal by util-linux's `script`, which merges stdout and stderr
// (and ends lines with \r\n, as a terminal does).
std::string OnTerminal(const std::string& command) {
  const std::string line = "script -qec " + Quote(std::string(TINBASE_CLI) + " " + command) +
                           " /dev/null 2>&1 </dev/null";
  FILE* pipe = popen(line.c_str(), "r");
  if (pipe == nullptr) return "popen failed";
  std::string out;
  std::array<char, 4096> buf;
  for (size_t n; (n = fread(buf.data(), 1, buf.size(), pipe)) > 0;) out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (status != 0) out += "\n[exit status " + std::to_string(status) + "]";
  return out;
}

TEST(ProgressCli, OnATerminalEveryLongCommandDrawsABarUnlessQuiet) {
  TempDir dir;
  const std::vector<std::string> commands = LongCommands(dir, "t", "");
  for (const std::string& command : commands) {
    const std::string out = OnTerminal(command);
    ASSERT_EQ(out.find("[exit status"), std::string::npos) << command << ": " << out;
    if (command.starts_with("init ")) continue;
    const std::string label = command.substr(0, command.find(" '"));
    EXPECT_NE(out.find(label + " ["), std::string::npos) << command << ": " << out;
    EXPECT_NE(out.find("] 100 %"), std::string::npos) << command << ": " << out;
  }
  for (const std::string& command : LongCommands(dir, "q", "--quiet ")) {
    const std::string out = OnTerminal(command);
    ASSERT_EQ(out.find("[exit status"), std::string::npos) << command << ": " << out;
    EXPECT_FALSE(HasBar(out)) << command << ": " << out;
  }
}

}  // namespace
}  // namespace tinbase::cli
