// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the model file read without LibTorch (stgf/model/trained_motion_model.hpp: the
// zip archive, its pickle, the tensors, the configuration and the checksum), seeded with the tests'
// small model (tests/model/data). A file that loads must also forecast.
#include "reader_contract.hpp"
#include "stgf/model/trained_motion_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return stgf::fuzz::check_reader(data, size, [](std::string_view bytes) {
    const stgf::TrainedMotionModel model = stgf::TrainedMotionModel::parse(std::string(bytes), "m.pt");
    stgf::MotionGraph graph{"s", "v", 1.0, {}};
    graph.objects.push_back({"a", {stgf::Vector3d(0, 0, 0), stgf::Vector3d(0.1, 0, 0)}, {0.0, 0.2}});
    graph.objects.push_back({"b", {stgf::Vector3d(1, 0, 0)}, {0.2}});
    (void)model.forecast(std::span(&graph, 1));
  });
}
