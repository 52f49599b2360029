// SPDX-License-Identifier: Apache-2.0
#pragma once
// An output file that appears whole or not at all: text goes to a temporary file beside the
// target, and commit() renames it into place. If commit() is never reached (an error, an
// exception), the destructor removes the temporary file and the target is left untouched.

#include <fstream>
#include <string>

namespace stgf {

class OutputFile {
 public:
  explicit OutputFile(std::string path);  // throws std::runtime_error if it cannot be created
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::ofstream& stream() { return stream_; }
  void commit();  // throws std::runtime_error on a write or rename failure

 private:
  std::string path_;
  std::string temporary_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Writes `text` to `path` through an OutputFile.
void write_text_file(const std::string& path, const std::string& text);

}  // namespace stgf
