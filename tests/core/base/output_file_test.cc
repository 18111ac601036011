// OutputFile: the final path appears only on Commit, whole; a writer that fails or never commits
// leaves nothing behind; paths that cannot be written are refused before anything is written.
#include "core/base/output_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t FilesIn(const std::string& dir) {
  return static_cast<size_t>(std::distance(std::filesystem::directory_iterator(dir),
                                           std::filesystem::directory_iterator()));
}

TEST(OutputFileTest, CommitRenamesTheTemporaryFileOntoThePath) {
  TempDir dir;
  const std::string path = dir.Path("out.obj");
  {
    std::ofstream(path) << "old";
    auto out = OutputFile::Create(path);
    ASSERT_TRUE(out.ok()) << out.status().ToString();
    EXPECT_NE(out->temp_path(), path);
    std::ofstream(out->temp_path()) << "new";
    EXPECT_EQ(Read(path), "old") << "the old file is replaced only on Commit";
    ASSERT_TRUE(out->Commit().ok());
  }
  EXPECT_EQ(Read(path), "new");
  EXPECT_EQ(FilesIn(dir.dir()), 1u);
}

TEST(OutputFileTest, NoCommitLeavesNothingBehind) {
  TempDir dir;
  const std::string path = dir.Path("out.glb");
  {
    auto out = OutputFile::Create(path);
    ASSERT_TRUE(out.ok());
    std::ofstream(out->temp_path()) << "half a file";
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_EQ(FilesIn(dir.dir()), 0u);
}

TEST(OutputFileTest, CommitWithoutAFileIsAnError) {
  TempDir dir;
  auto out = OutputFile::Create(dir.Path("out.ply"));
  ASSERT_TRUE(out.ok());
  Status committed = out->Commit();
  EXPECT_EQ(committed.code(), StatusCode::kIOError);
  EXPECT_NE(committed.message().find("out.ply"), std::string::npos) << committed.message();
}

TEST(OutputFileTest, UnwritablePathsAreRefusedNamingThePath) {
  TempDir dir;
  for (const std::string& path : {dir.Path("no/such/dir/out.obj"), dir.dir()}) {
    auto out = OutputFile::Create(path);
    EXPECT_EQ(out.status().code(), StatusCode::kIOError) << path;
    EXPECT_NE(out.status().message().find(path), std::string::npos) << out.status().message();
  }
  EXPECT_EQ(OutputFile::Create("").status().code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace tinbase
