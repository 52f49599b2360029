// SPDX-License-Identifier: Apache-2.0
// The general model built into the library (model/general_model.hpp): models/general.pt itself, a
// model for ours and ours-l, and what load_model_for gives without a path. Its numbers on the
// validation splits are checked by Cli.ShippedGeneralModelKeepsItsValidationNumbers.

#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "stgf/model/general_model.hpp"
#include "stgf/model/named_methods.hpp"

namespace stgf {
namespace {

std::string file_bytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

TEST(GeneralModel, IsTheShippedFileAndAFusedHistoryModel) {
  if (general_model_bytes().empty()) {
    EXPECT_THROW(general_model(), std::invalid_argument);
    EXPECT_THROW(load_model_for("ours", ""), std::invalid_argument);
    GTEST_SKIP() << "built with -DSTGF_GENERAL_MODEL=OFF";
  }
  EXPECT_EQ(general_model_bytes(), file_bytes(STGF_SOURCE_DIR "/models/general.pt"));
  const TrainedMotionModel model = general_model();
  EXPECT_EQ(model.metadata().at("input"), "fused");
  // Trained on three benchmarks, with the registration prior calibrated on their validation splits.
  EXPECT_EQ(model.metadata().at("benchmark").size(), 3U);
  EXPECT_TRUE(model.metadata().contains("registration"));
  EXPECT_GT(model.prediction_horizon(), 0.0);
  // Without a path, ours and ours-l get it; sttp, whose model learns from one view's raw
  // measurements, has none.
  EXPECT_EQ(load_model_for("ours", "").metadata(), model.metadata());
  EXPECT_EQ(load_model_for("ours-l", "").metadata(), model.metadata());
  EXPECT_THROW(load_model_for("sttp", ""), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
