// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the measurements reader (stgf/io/measurement_file.hpp).
#include "reader_contract.hpp"
#include "stgf/io/measurement_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return stgf::fuzz::check_reader(data, size, [](std::string_view text) { stgf::parse_measurements("m.csv", text); });
}
