// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/output_file.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include <unistd.h>

namespace stgf {

OutputFile::OutputFile(std::string path)
    : path_(std::move(path)), temporary_path_(path_ + ".tmp." + std::to_string(::getpid())) {
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
