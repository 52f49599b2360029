// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the model file reader (MotionModel::load, stgf/learn/motion_model.hpp). The
// bytes go to a file first, as a user's model file would.
#include <unistd.h>

#include <fstream>

#include "fuzz_csv_readers.hpp"
#include "stgf/learn/motion_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = "/tmp/stgf_fuzz_model_" + std::to_string(::getpid()) + ".pt";
  {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  return stgf::fuzz::check_reader(data, size, [](std::string_view) { stgf::MotionModel::load(path); });
}
