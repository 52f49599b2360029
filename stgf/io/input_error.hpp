// SPDX-License-Identifier: Apache-2.0
#pragma once
// Bad input: the message names the file as the user gave it and the line (the header is line 1),
// "FILE:LINE: what is wrong". The CLI turns it into exit status 2 with no output written.

#include <stdexcept>
#include <string>

namespace stgf {

class InputError : public std::runtime_error {
 public:
  // line 0 means the file as a whole ("FILE: what").
  InputError(const std::string& file, int line, const std::string& what);

  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

}  // namespace stgf
