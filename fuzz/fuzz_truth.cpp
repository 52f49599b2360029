// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the truth reader (stgf/io/truth_file.hpp), whole and scene by scene.
#include "reader_contract.hpp"
#include "stgf/io/truth_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stgf::fuzz::check_reader(data, size, [](std::string_view text) { stgf::parse_truth("t.csv", text); });
  // As `stgf eval` reads it: one scene at a time.
  return stgf::fuzz::check_reader(data, size, [](std::string_view text) {
    stgf::TruthSceneReader reader = stgf::TruthSceneReader::from_text("t.csv", std::string(text));
    stgf::TruthFile scene;
    while (reader.read(scene)) {
    }
  });
}
