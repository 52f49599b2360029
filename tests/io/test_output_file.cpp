// SPDX-License-Identifier: Apache-2.0
// Output files are written whole or not at all, and a killed writer's temporary does not stay.
#include "stgf/io/output_file.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

namespace stgf {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream file(path);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// The id of a process that has exited.
pid_t finished_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(OutputFile, UncommittedLeavesTheTargetAlone) {
  const fs::path directory = fs::path(::testing::TempDir()) / ("stgf_output_" + std::to_string(::getpid()));
  fs::create_directories(directory);
  const std::string target = (directory / "out.csv").string();
  write_text_file(target, "previous\n");
  {
    OutputFile file(target);
    file.stream() << "half";
  }  // no commit: an error happened
  EXPECT_EQ(slurp(target), "previous\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory), fs::directory_iterator()), 1);
  fs::remove_all(directory);
}

TEST(OutputFile, KilledWritersTemporaryIsRemovedByTheNextWriter) {
  const fs::path directory = fs::path(::testing::TempDir()) / ("stgf_stale_" + std::to_string(::getpid()));
  fs::create_directories(directory);
  const fs::path target = directory / "out.csv";
  const fs::path stale = directory / ("out.csv.tmp." + std::to_string(finished_process()));
  const fs::path live = directory / ("out.csv.tmp." + std::to_string(::getppid()));  // a writer still running
  const fs::path other = directory / "other.csv.tmp.1";
  for (const fs::path& path : {stale, live, other}) std::ofstream(path) << "partial";
  write_text_file(target.string(), "new\n");
  EXPECT_EQ(slurp(target), "new\n");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
  fs::remove_all(directory);
}

}  // namespace
}  // namespace stgf
