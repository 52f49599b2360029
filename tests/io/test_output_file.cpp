// SPDX-License-Identifier: Apache-2.0
// Output files are written whole or not at all, and a killed writer's temporary does not stay.
#include "stgf/io/output_file.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using testing::entries_of;
using testing::file_bytes;
using testing::ScratchDirectory;

// The id of a process that has exited.
pid_t finished_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(OutputFile, UncommittedLeavesTheTargetAlone) {
  const ScratchDirectory directory;
  const std::string target = directory / "out.csv";
  write_text_file(target, "previous\n");
  {
    OutputFile file(target);
    file.stream() << "half";
  }  // no commit: an error happened
  EXPECT_EQ(file_bytes(target), "previous\n");
  EXPECT_EQ(entries_of(directory.path()), std::vector<std::string>{"out.csv"});
}

TEST(OutputFile, KilledWritersTemporaryIsRemovedByTheNextWriter) {
  const ScratchDirectory directory;
  const std::string target = directory / "out.csv";
  const std::string stale = directory.write("out.csv.tmp." + std::to_string(finished_process()), "partial");
  const std::string live = directory.write("out.csv.tmp." + std::to_string(::getppid()), "partial");  // still running
  const std::string other = directory.write("other.csv.tmp.1", "partial");
  write_text_file(target, "new\n");
  EXPECT_EQ(file_bytes(target), "new\n");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(other));
}

}  // namespace
}  // namespace stgf
