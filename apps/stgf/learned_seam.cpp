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

constexpr const char* kAtenVariable = "ATEN_CPU_CAPABILITY";
constexpr const char* kAtenPortable = "default";
constexpr const char* kOpenBlasVariable = "OPENBLAS_CORETYPE";
constexpr const char* kOpenBlasPortable = "Prescott";

void pin_portable_kernels() {
  ::setenv(kAtenVariable, kAtenPortable, /*overwrite=*/1);
  ::setenv(kOpenBlasVariable, kOpenBlasPortable, /*overwrite=*/1);
}

bool portable_kernels_pinned() {
  const char* aten = std::getenv(kAtenVariable);
  const char* openblas = std::getenv(kOpenBlasVariable);
  return aten != nullptr && std::strcmp(aten, kAtenPortable) == 0 && openblas != nullptr &&
         std::strcmp(openblas, kOpenBlasPortable) == 0;
}

}  // namespace

void ensure_portable_kernels() {
  if (portable_kernels_pinned()) return;
  std::vector<char*> arguments = command_line();
  if (arguments.empty()) throw std::logic_error("ensure_portable_kernels: remember_command_line was not called");
  pin_portable_kernels();
  ::execv("/proc/self/exe", arguments.data());
  throw std::runtime_error(std::string("cannot start stgf-learned again with portable kernels: ") + std::strerror(errno));
}

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
  for (const char* argument : arguments) {
    if (argument != nullptr && std::strcmp(argument, kPortableFlag) == 0) pin_portable_kernels();
  }
  ::execv(learned.c_str(), arguments.data());
  throw std::runtime_error("cannot start " + learned + ": " + std::strerror(errno));
}

}  // namespace stgf::cli
