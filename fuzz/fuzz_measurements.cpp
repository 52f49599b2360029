// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the measurements reader (stgf/io/measurement_file.hpp), whole and scene by scene.
#include "reader_contract.hpp"
#include "stgf/io/measurement_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stgf::fuzz::check_reader(data, size, [](std::string_view text) { stgf::parse_measurements("m.csv", text); });
  // As `stgf run` reads it: two scenes at a time.
  return stgf::fuzz::check_reader(data, size, [](std::string_view text) {
    stgf::MeasurementSceneReader reader = stgf::MeasurementSceneReader::from_text("m.csv", std::string(text));
    stgf::MeasurementFile block;
    while (reader.read(block, 2) > 0) {
    }
  });
}
