// SPDX-License-Identifier: Apache-2.0
#include "install_layout.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace fs = std::filesystem;

namespace stgf::cli {
namespace {

const char* environment(const char* name) {
  const char* value = std::getenv(name);
  return value != nullptr && *value != '\0' ? value : nullptr;
}

// share/stgf beside the executable or up to three levels above it; "" when there is none.
fs::path share_directory() {
  fs::path directory = executable_directory();
  for (int level = 0; level < 4 && !directory.empty(); ++level) {
    std::error_code error;
    const fs::path candidate = directory / "share" / "stgf";
    if (fs::is_directory(candidate, error)) return candidate;
    if (!directory.has_parent_path() || directory.parent_path() == directory) break;
    directory = directory.parent_path();
  }
  return {};
}

}  // namespace

std::string executable_directory() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (error) return fs::current_path().string();
  return executable.parent_path().string();
}

std::string shipped_data_directory() {
  if (const char* overridden = environment("STGF_DATA_DIR")) return overridden;
  const fs::path share = share_directory();
  std::error_code error;
  if (share.empty() || !fs::is_directory(share / "data", error)) {
    throw std::runtime_error("cannot find stgf's shipped data (share/stgf/data beside or above " +
                             executable_directory() + "); set STGF_DATA_DIR or give --source");
  }
  return (share / "data").string();
}

std::string default_kitti_directory() {
  if (const char* overridden = environment("STGF_KITTI_DIR")) return overridden;
  const fs::path share = share_directory();
  return share.empty() ? std::string("share/stgf/kitti_tracking") : (share / "kitti_tracking").string();
}

std::string learned_cli_path() {
  const fs::path here = executable_directory();
  std::error_code error;
  for (const fs::path& candidate :
       {here / "libexec" / "stgf" / "stgf-learned", here.parent_path() / "libexec" / "stgf" / "stgf-learned",
        here / "stgf-learned"}) {
    if (fs::is_regular_file(candidate, error)) return candidate.string();
  }
  return {};
}

}  // namespace stgf::cli
