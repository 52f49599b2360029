// SPDX-License-Identifier: Apache-2.0
// A model file read and run without LibTorch (model/trained_motion_model.hpp), on a small model
// written by `MotionModel::save` (tests/model/data/tiny-motion-model.pt: history 3, embedding 4,
// hidden 4, attention 3, seed 5; test_learn checks that LibTorch reads it the same).

#include "stgf/model/trained_motion_model.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "model/zip_builder.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

using ::testing::HasSubstr;
using namespace std::string_literals;

const std::string kFixture = std::string(STGF_SOURCE_DIR) + "/tests/model/data/tiny-motion-model.pt";

const std::string& fixture_bytes() {
  static const std::string bytes = [] {
    std::ifstream file(kFixture, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  }();
  return bytes;
}

// Two graphs of objects walking on circles, sampled every 0.2 s (the fixture's period).
std::vector<MotionGraph> walking_graphs() {
  std::vector<MotionGraph> graphs;
  for (int g = 0; g < 2; ++g) {
    MotionGraph graph{"scene", "v" + std::to_string(g), 1.0, {}};
    for (int i = 0; i < 3 + g * 3; ++i) {
      ObjectHistory history{"o" + std::to_string(i), {}, {}};
      for (int k = 0; k < 4; ++k) {
        const double t = 0.2 * k;
        history.positions.emplace_back(i + std::cos(t + i), 0.5 * i + std::sin(t), 0.0);
        history.times.push_back(t);
      }
      graph.objects.push_back(std::move(history));
    }
    graphs.push_back(std::move(graph));
  }
  return graphs;
}

std::string error_of(const std::string& bytes) {
  try {
    TrainedMotionModel::parse(bytes, "m.pt");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(TrainedMotionModel, ReadsTheModelFileWithItsSettings) {
  const TrainedMotionModel model = TrainedMotionModel::load(kFixture);
  EXPECT_EQ(model.shape().history_length, 3);
  EXPECT_EQ(model.shape().hidden, 4);
  EXPECT_EQ(model.shape().attention_hidden, 3);
  EXPECT_EQ(model.normalisation().speed, 1.3);
  EXPECT_EQ(model.normalisation().longest_interval, 0.5);
  EXPECT_EQ(model.history_positions(), 4);
  EXPECT_EQ(model.prediction_horizon(), kHorizonFactor * 0.5);
  EXPECT_EQ(model.history_spacing(), kHistorySpacingFactor * 0.2);
  EXPECT_EQ(model.process_noise(0.2), 0.02 * Matrix3d::Identity());
  EXPECT_LT((model.process_noise(0.4) - 0.08 * Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_EQ(model.metadata().value("input", ""), "fused");
  EXPECT_EQ(model.metadata().at("registration").at("noise_ratio").get<double>(), 0.5);
}

// Each object's forecast depends on its own graph only: the same alone as with other graphs.
// Q at longer intervals and the coasting curve go into the file's config and come back; a model
// without them writes the config it wrote before they existed (no new keys), so its file is unchanged.
TEST(TrainedMotionModel, SettingsKeepQAtLongerIntervalsAndOnlyWhenThereAreAny) {
  MotionModelSettings settings = TrainedMotionModel::load(kFixture).settings();
  const nlohmann::json before = settings_json(settings);
  EXPECT_FALSE(before.at("process_noise").contains("intervals"));
  EXPECT_FALSE(before.at("process_noise").contains("coasting"));
  EXPECT_FALSE(before.at("normalisation").contains("frame_period"));  // s_t's: one benchmark's
  const double period = settings.process_noise_period;
  settings.process_noise_intervals = {{2.0 * period, 0.02 * Matrix3d::Identity()}};
  settings.coasting_process_noise = {{4.0 * period, 0.05 * Matrix3d::Identity()},
                                     {6.0 * period, 0.09 * Matrix3d::Identity()}};
  const MotionModelSettings back = settings_from_json(nlohmann::json::parse(settings_json(settings).dump()));
  ASSERT_EQ(back.process_noise_intervals.size(), 1u);
  ASSERT_EQ(back.coasting_process_noise.size(), 2u);
  EXPECT_EQ(back.process_noise_intervals[0].interval, 2.0 * period);
  EXPECT_EQ(back.coasting_process_noise[1].covariance, 0.09 * Matrix3d::Identity());
  // Nodes out of order are refused.
  nlohmann::json config = settings_json(settings);
  config["process_noise"]["coasting"][1]["interval"] = 3.0 * period;
  EXPECT_THROW(settings_from_json(config), std::invalid_argument);
  // The fastest training data's frame period, where it differs from s_t, goes in and comes back; a
  // scale that is not positive is refused.
  settings.normalisation.frame_period = 0.5 * settings.normalisation.period;
  const MotionModelSettings faster = settings_from_json(nlohmann::json::parse(settings_json(settings).dump()));
  EXPECT_EQ(faster.normalisation.frame_period, 0.5 * settings.normalisation.period);
  EXPECT_EQ(motion_model_history_spacing(faster.normalisation), kHistorySpacingFactor * 0.5 * settings.normalisation.period);
  for (const char* scale : {"frame_period", "period", "speed"}) {
    nlohmann::json bad = settings_json(settings);
    bad["normalisation"][scale] = 0.0;
    EXPECT_THROW(settings_from_json(bad), std::invalid_argument) << scale;
  }
}

TEST(TrainedMotionModel, ForecastsEachGraphOnItsOwn) {
  const TrainedMotionModel model = TrainedMotionModel::load(kFixture);
  const std::vector<MotionGraph> graphs = walking_graphs();
  const auto together = model.forecast(graphs);
  ASSERT_EQ(together.size(), 2u);
  for (std::size_t g = 0; g < graphs.size(); ++g) {
    const auto alone = model.forecast(std::span(&graphs[g], 1));
    ASSERT_EQ(alone[0].size(), graphs[g].objects.size());
    for (std::size_t i = 0; i < alone[0].size(); ++i) {
      EXPECT_TRUE(alone[0][i].acceleration.allFinite());
      EXPECT_EQ(alone[0][i].acceleration, together[g][i].acceleration);
      EXPECT_EQ(alone[0][i].velocity, together[g][i].velocity);
    }
  }
  EXPECT_TRUE(model.forecast({}).empty());
}

TEST(TrainedMotionModel, MissingOrForeignFilesAreInputErrors) {
  try {
    TrainedMotionModel::load("/nonexistent/model.pt");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("/nonexistent/model.pt: no such model file"));
  }
  EXPECT_THAT(error_of("this is not a model"), HasSubstr("m.pt: not a readable model file"));
  // A valid archive that is not a stgf model.
  const std::string other = stgf::testing::zip_of(
      {{"archive/data.pkl", "\x80\x02" "c__torch__\nModule\n)\x81}(X\x01\x00\x00\x00" "aK\x01ub."s}});
  EXPECT_THAT(error_of(other), HasSubstr("not a stgf motion model"));
}

// A weight changed (the archive's own CRC made right, as a careless edit would): the checksum says so.
TEST(TrainedMotionModel, AChangedWeightFailsTheChecksum) {
  const std::string name = "archive/data/2";
  std::string weights = stgf::testing::record_of(fixture_bytes(), name);
  ASSERT_GE(weights.size(), 4u);
  float first;
  std::memcpy(&first, weights.data(), sizeof first);
  first = std::nextafter(first, 1.0f);
  std::memcpy(weights.data(), &first, sizeof first);
  EXPECT_THAT(error_of(stgf::testing::with_record(fixture_bytes(), name, weights)),
              HasSubstr("its weights or settings do not match its checksum"));
  // A weight made infinite: refused as such before the checksum.
  first = std::numeric_limits<float>::infinity();
  std::memcpy(weights.data(), &first, sizeof first);
  EXPECT_THAT(error_of(stgf::testing::with_record(fixture_bytes(), name, weights)), HasSubstr("is not finite"));
}

// Every byte of the file flipped in turn, and the file cut at every length: refused with an
// InputError, or (a byte of a record nothing reads, such as LibTorch's compressed code) the same model.
TEST(TrainedMotionModel, EveryDamagedByteIsRefusedOrHarmless) {
  const std::string& bytes = fixture_bytes();
  const std::vector<MotionGraph> graphs = walking_graphs();
  const auto expected = TrainedMotionModel::parse(bytes, "m.pt").forecast(graphs);
  std::size_t refused = 0, harmless = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x5a);
    try {
      const auto forecasts = TrainedMotionModel::parse(damaged, "m.pt").forecast(graphs);
      for (std::size_t g = 0; g < expected.size(); ++g) {
        for (std::size_t i = 0; i < expected[g].size(); ++i) {
          ASSERT_EQ(forecasts[g][i].acceleration, expected[g][i].acceleration) << "byte " << at;
        }
      }
      ++harmless;
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, bytes.size() / 4);
  EXPECT_GT(harmless, 0u);
  for (std::size_t size = 0; size < bytes.size(); size += 7) {
    EXPECT_THAT(error_of(bytes.substr(0, size)), HasSubstr("m.pt")) << "cut to " << size;
  }
}

}  // namespace
}  // namespace stgf
