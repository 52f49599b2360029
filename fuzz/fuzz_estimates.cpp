// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the estimates reader (stgf/io/estimate_file.hpp), whole and scene by scene.
#include "reader_contract.hpp"
#include "stgf/io/estimate_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stgf::fuzz::check_reader(data, size, [](std::string_view text) { stgf::parse_estimates("e.csv", text); });
  // As `stgf eval` reads it: one scene at a time.
  return stgf::fuzz::check_reader(data, size, [](std::string_view text) {
    stgf::EstimateSceneReader reader = stgf::EstimateSceneReader::from_text("e.csv", std::string(text));
    stgf::EstimateFile scene;
    while (reader.read(scene)) {
    }
  });
}
