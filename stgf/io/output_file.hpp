// SPDX-License-Identifier: Apache-2.0
#pragma once
// An output file that appears whole or not at all: text goes to a temporary file beside the
// target, and commit() renames it into place. If commit() is never reached (an error, an
// exception), the destructor removes the temporary file and the target is left untouched. A
// process killed outright cannot clean up: its PATH.tmp.PID is removed by the next OutputFile for
// PATH (remove_stale_temporaries).

#include <fstream>
#include <string>

namespace stgf {

// Removes PATH.tmp.PID files whose process no longer exists (a writer killed before it finished).
void remove_stale_temporaries(const std::string& path);

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
