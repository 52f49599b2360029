// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/output_file.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <signal.h>
#include <unistd.h>

#include <cerrno>

namespace stgf {

void remove_stale_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = target.filename().string() + ".tmp.";
  std::error_code error;
  for (fs::directory_iterator it(directory, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string pid_text = name.substr(prefix.size());
    if (pid_text.empty() || pid_text.find_first_not_of("0123456789") != std::string::npos) continue;
    const long pid = std::stol(pid_text);
    // kill(pid, 0) fails with ESRCH when no such process exists: its writer was killed.
    if (pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

OutputFile::OutputFile(std::string path)
    : path_(std::move(path)), temporary_path_(path_ + ".tmp." + std::to_string(::getpid())) {
  remove_stale_temporaries(path_);
  stream_.open(temporary_path_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw std::runtime_error(path_ + ": cannot create the file");
}

OutputFile::~OutputFile() {
  if (committed_) return;
  stream_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

void OutputFile::commit() {
  stream_.flush();
  if (!stream_) throw std::runtime_error(path_ + ": write failed");
  stream_.close();
  if (std::rename(temporary_path_.c_str(), path_.c_str()) != 0) {
    throw std::runtime_error(path_ + ": cannot move the finished file into place");
  }
  committed_ = true;
}

void write_text_file(const std::string& path, const std::string& text) {
  OutputFile file(path);
  file.stream() << text;
  file.commit();
}

}  // namespace stgf
