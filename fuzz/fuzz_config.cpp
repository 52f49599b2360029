// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the YAML method settings reader (stgf/io/method_config_file.hpp).
#include "reader_contract.hpp"
#include "stgf/io/method_config_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return stgf::fuzz::check_reader(data, size, [](std::string_view text) {
    stgf::parse_method_config("c.yaml", std::string(text));
  });
}
