// SPDX-License-Identifier: Apache-2.0
#include "learned_seam.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "install_layout.hpp"

namespace stgf::cli {
namespace {

std::vector<char*>& command_line() {
  static std::vector<char*> arguments;
  return arguments;
}

}  // namespace

void remember_command_line(int argc, char** argv) {
  command_line().assign(argv, argv + argc);
  command_line().push_back(nullptr);
}

void hand_over_to_learned_cli(const std::string& what) {
  const std::string learned = learned_cli_path();
  if (learned.empty()) {
    throw std::runtime_error(what + " needs the learned motion model, and this stgf was built without LibTorch "
                             "(no stgf-learned beside it: build with -DSTGF_WITH_LIBTORCH=ON)");
  }
  std::vector<char*> arguments = command_line();
  if (arguments.empty()) throw std::logic_error("hand_over_to_learned_cli: remember_command_line was not called");
  // LibTorch's OpenMP threads wait for work by spinning, which on a machine where another job holds a
  // core made 2 training threads 2.5× slower than one; sleeping instead costs little when idle. Read
  // when OpenMP starts, so it is set here, before stgf-learned loads it (unless the user set it).
  ::setenv("OMP_WAIT_POLICY", "PASSIVE", /*overwrite=*/0);
  ::execv(learned.c_str(), arguments.data());
  throw std::runtime_error("cannot start " + learned + ": " + std::strerror(errno));
}

}  // namespace stgf::cli
