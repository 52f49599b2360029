// SPDX-License-Identifier: Apache-2.0
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "stgf/io/input_error.hpp"
#include "stgf/io/method_config_file.hpp"

namespace stgf {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_method_config("c.yaml", text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(MethodConfigFile, EmptyFileKeepsDefaults) {
  const MethodConfig config = parse_method_config("c.yaml", "# nothing\n");
  EXPECT_DOUBLE_EQ(config.mmt.initial_position_variance, 10.0);
  EXPECT_DOUBLE_EQ(config.mmt.initial_velocity_variance, 1e6);
  EXPECT_DOUBLE_EQ(config.mmt.position_noise_density, 10.0);
  EXPECT_DOUBLE_EQ(config.mmt.velocity_noise_density, 10.0);
}

TEST(MethodConfigFile, ReadsMmtSettings) {
  const MethodConfig config =
      parse_method_config("c.yaml", "mmt:\n  position_noise_density: 0.5\n  velocity_noise_density: 2\n");
  EXPECT_DOUBLE_EQ(config.mmt.position_noise_density, 0.5);
  EXPECT_DOUBLE_EQ(config.mmt.velocity_noise_density, 2.0);
  EXPECT_DOUBLE_EQ(config.mmt.initial_position_variance, 10.0);
}

TEST(MethodConfigFile, ErrorsNameTheLine) {
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: 1\n  velocity_nosie_density: 2\n"),
            "c.yaml:3: unknown setting 'mmt.velocity_nosie_density'");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: fast\n"),
            "c.yaml:2: mmt.position_noise_density must be a number");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: -1\n"),
            "c.yaml:2: mmt.position_noise_density must be a finite number > 0");
  EXPECT_EQ(error_of("# c\nkalman:\n  a: 1\n"), "c.yaml:2: unknown section 'kalman' (known: wls, mmt, ours)");
  EXPECT_EQ(error_of("mmt: [1, 2\n"), error_of("mmt: [1, 2\n"));  // deterministic parse errors
  EXPECT_NE(error_of("mmt: [1, 2\n").find("c.yaml:"), std::string::npos);
}

TEST(MethodConfigFile, DuplicateKeysAreErrors) {
  EXPECT_EQ(error_of("ours:\n  lag_window_s: 1\n  tracks: per-view\n  lag_window_s: 2\n"),
            "c.yaml:4: duplicate key 'lag_window_s' (first at line 2)");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: 1\nmmt:\n  position_noise_density: 2\n"),
            "c.yaml:3: duplicate key 'mmt' (first at line 1)");
}

// Found by fuzz_config: a 2,500-character key was echoed whole.
TEST(MethodConfigFile, LongNamesAreQuotedInPart) {
  const std::string message = error_of(std::string(1000, 'k') + ": 1\n");
  EXPECT_LT(message.size(), 200u) << message;
  EXPECT_NE(message.find("(1000 characters) (known: wls, mmt, ours)"), std::string::npos) << message;
}

TEST(MethodConfigFile, KeysMustBePlainNames) {
  EXPECT_EQ(error_of("ours:\n  [a, b]: 1\n"), "c.yaml:2: a setting's name must be a plain word");
}

TEST(MethodConfigFile, DirectoryIsNotAConfig) {
  const std::string directory = ::testing::TempDir();
  try {
    read_method_config(directory);
    ADD_FAILURE() << "a directory was read as a config";
  } catch (const InputError& error) {
    EXPECT_THAT(std::string(error.what()), ::testing::HasSubstr("is a directory, not a YAML file"));
  }
}

TEST(MethodConfigFile, OursDefaults) {
  const MethodConfig config = parse_method_config("c.yaml", "mmt:\n  position_noise_density: 0.5\n");
  EXPECT_TRUE(config.ours.registration);
  EXPECT_FALSE(config.ours.translation_sigma.has_value());
  EXPECT_FALSE(config.ours.noise_ratio.has_value());
}

TEST(MethodConfigFile, ReadsOursSettings) {
  const MethodConfig listed =
      parse_method_config("c.yaml",
                          "ours:\n  registration: false\n  registration_translation_sigma_m: [0.3, 0.2, 0]\n"
                          "  registration_noise_ratio: 0.5\n");
  EXPECT_FALSE(listed.ours.registration);
  ASSERT_TRUE(listed.ours.translation_sigma.has_value());
  EXPECT_EQ(*listed.ours.translation_sigma, Vector3d(0.3, 0.2, 0.0));
  ASSERT_TRUE(listed.ours.noise_ratio.has_value());
  EXPECT_EQ(*listed.ours.noise_ratio, Vector3d::Constant(0.5));
  EXPECT_DOUBLE_EQ(listed.mmt.position_noise_density, 10.0);  // the other section keeps its defaults

  // One number: the same σ on every axis; a ratio of 0 is allowed (no noise-unit offset).
  const MethodConfig scalar = parse_method_config(
      "c.yaml",
      "mmt:\n  velocity_noise_density: 2\nours:\n  registration_translation_sigma_m: 0.25\n"
      "  registration_noise_ratio: 0\n");
  EXPECT_TRUE(scalar.ours.registration);
  ASSERT_TRUE(scalar.ours.translation_sigma.has_value());
  EXPECT_EQ(*scalar.ours.translation_sigma, Vector3d::Constant(0.25));
  ASSERT_TRUE(scalar.ours.noise_ratio.has_value());
  EXPECT_EQ(*scalar.ours.noise_ratio, Vector3d::Zero());
  // A list of three: α along, across and vertical to each measurement's ray.
  const MethodConfig axes =
      parse_method_config("c.yaml", "ours:\n  registration_noise_ratio: [0.1, 0.6, 0.3]\n");
  ASSERT_TRUE(axes.ours.noise_ratio.has_value());
  EXPECT_EQ(*axes.ours.noise_ratio, Vector3d(0.1, 0.6, 0.3));
  EXPECT_FALSE(axes.ours.range_scale_sigma.has_value());
  const MethodConfig scale = parse_method_config("c.yaml", "ours:\n  registration_range_scale_sigma: 0.008\n");
  ASSERT_TRUE(scale.ours.range_scale_sigma.has_value());
  EXPECT_EQ(*scale.ours.range_scale_sigma, 0.008);
  EXPECT_DOUBLE_EQ(scalar.mmt.velocity_noise_density, 2.0);

  EXPECT_TRUE(parse_method_config("c.yaml", "ours:\n  registration: true\n").ours.registration);
}

TEST(MethodConfigFile, OursErrorsNameTheLine) {
  EXPECT_EQ(error_of("ours:\n  registration: true\n  registration_noise_ratio: -0.5\n"),
            "c.yaml:3: ours.registration_noise_ratio must be a finite number >= 0");
  EXPECT_EQ(error_of("ours:\n  registration_noise_ratio: lots\n"),
            "c.yaml:2: ours.registration_noise_ratio must be a number");
  EXPECT_EQ(
      error_of("ours:\n  registration_translation_sigma_m: [0.3, 0.2]\n"),
      "c.yaml:2: ours.registration_translation_sigma_m must be one number or a list of three (x, y, z)");
  EXPECT_EQ(error_of("ours:\n  registration_noise_ratio: [0.3, 0.2, 0.1, 0.0]\n"),
            "c.yaml:2: ours.registration_noise_ratio must be one number or a list of three (along, across, vertical)");
  EXPECT_EQ(error_of("ours:\n  registration_noise_ratio: [0.3, -0.2, 0.1]\n"),
            "c.yaml:2: ours.registration_noise_ratio must be a finite number >= 0");
  EXPECT_EQ(error_of("ours:\n  registration_prior_scale: everywhere\n"),
            "c.yaml:2: ours.registration_prior_scale must be auto, per-scene, across-scenes or shrink-across-scenes");
  using enum RegistrationScaleLearning;
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  registration_prior_scale: across-scenes\n").ours.registration_scale_learning,
            kAcrossScenes);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  registration_prior_scale: per-scene\n").ours.registration_scale_learning,
            kPerScene);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  registration_prior_scale: shrink-across-scenes\n").ours.registration_scale_learning,
            kShrinkAcrossScenes);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  registration_prior_scale: auto\n").ours.registration_scale_learning,
            std::nullopt);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  lag_window_s: 1\n").ours.registration_scale_learning, std::nullopt);
  EXPECT_EQ(error_of("ours:\n  adapt_process_noise: true\n  process_noise_scale: pooled\n"),
            "c.yaml:3: ours.process_noise_scale must be auto, per-scene, across-scenes or grow-across-scenes");
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  process_noise_scale: across-scenes\n").ours.process_noise_scale_learning,
            ProcessNoiseScaleLearning::kAcrossScenes);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  process_noise_scale: grow-across-scenes\n").ours.process_noise_scale_learning,
            ProcessNoiseScaleLearning::kGrowAcrossScenes);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  process_noise_scale: per-scene\n").ours.process_noise_scale_learning,
            ProcessNoiseScaleLearning::kPerScene);
  EXPECT_FALSE(parse_method_config("c.yaml", "ours:\n  process_noise_scale: auto\n").ours.process_noise_scale_learning);
  EXPECT_FALSE(MethodConfig{}.ours.process_noise_scale_learning.has_value());
  EXPECT_EQ(error_of("ours:\n  registration_range_scale_sigma: -0.01\n"),
            "c.yaml:2: ours.registration_range_scale_sigma must be a finite number >= 0");
  EXPECT_EQ(error_of("ours:\n  registration_range_scale_sigma: [0.01, 0.02]\n"),
            "c.yaml:2: ours.registration_range_scale_sigma must be a number");
  EXPECT_EQ(error_of("ours:\n  registration_translation_sigma_m:\n    - 0.3\n    - -0.2\n    - 0\n"),
            "c.yaml:4: ours.registration_translation_sigma_m must be a finite number >= 0");
  EXPECT_EQ(error_of("ours:\n  registration_translation_sigma_m: -1\n"),
            "c.yaml:2: ours.registration_translation_sigma_m must be a finite number >= 0");
  EXPECT_EQ(error_of("ours:\n\n  registration: maybe\n"),
            "c.yaml:3: ours.registration must be true or false");
  EXPECT_EQ(error_of("ours:\n  registration: 1.5\n"), "c.yaml:2: ours.registration must be true or false");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: 1\nours:\n  registration: true\n  foo: 1\n"),
            "c.yaml:5: unknown setting 'ours.foo'");
  EXPECT_EQ(error_of("ours: [1, 2]\n"), "c.yaml:1: ours must be a mapping of settings");
  // The same through the file reader: the message names the file.
  const std::string path = ::testing::TempDir() + "stgf_ours_config.yaml";
  std::ofstream(path) << "ours:\n  registration_noise_ratio: -1\n";
  try {
    read_method_config(path);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), path);
    EXPECT_EQ(error.line(), 2);
  }
}

// The shipped, documented config holds exactly the defaults.
TEST(MethodConfigFile, ShippedConfigHoldsTheDefaults) {
  const MethodConfig shipped = read_method_config(STGF_SOURCE_DIR "/config/methods.yaml");
  const MethodConfig defaults;
  EXPECT_EQ(shipped.mmt.initial_position_variance, defaults.mmt.initial_position_variance);
  EXPECT_EQ(shipped.mmt.initial_velocity_variance, defaults.mmt.initial_velocity_variance);
  EXPECT_EQ(shipped.mmt.position_noise_density, defaults.mmt.position_noise_density);
  EXPECT_EQ(shipped.mmt.velocity_noise_density, defaults.mmt.velocity_noise_density);
  EXPECT_EQ(shipped.ours.registration, defaults.ours.registration);
  EXPECT_EQ(shipped.ours.translation_sigma.has_value(), defaults.ours.translation_sigma.has_value());
  EXPECT_EQ(shipped.ours.noise_ratio.has_value(), defaults.ours.noise_ratio.has_value());
  EXPECT_EQ(shipped.ours.per_view_tracks, defaults.ours.per_view_tracks);
  EXPECT_EQ(shipped.ours.lag_window, defaults.ours.lag_window);
  EXPECT_EQ(shipped.ours.stop_on_late, defaults.ours.stop_on_late);
  EXPECT_EQ(shipped.ours.motion_fallback, defaults.ours.motion_fallback);
  EXPECT_EQ(shipped.ours.cross_view_weights, defaults.ours.cross_view_weights);
  EXPECT_EQ(shipped.ours.history_velocity_error, defaults.ours.history_velocity_error);
}

// Down-weighting a measurement the other views place far off (core/cross_view_weights.hpp): on by default.
TEST(MethodConfigFile, ReadsTheCrossViewWeights) {
  EXPECT_TRUE(MethodConfig{}.ours.cross_view_weights);
  EXPECT_FALSE(parse_method_config("c.yaml", "ours:\n  cross_view_weights: false\n").ours.cross_view_weights);
  EXPECT_EQ(error_of("ours:\n  cross_view_weights: maybe\n"), "c.yaml:2: ours.cross_view_weights must be true or false");
}

// The history's velocity error in a forecast's covariance (core/object_track.hpp): on by default.
TEST(MethodConfigFile, ReadsTheHistoryVelocityError) {
  EXPECT_TRUE(MethodConfig{}.ours.history_velocity_error);
  EXPECT_FALSE(parse_method_config("c.yaml", "ours:\n  history_velocity_error: false\n").ours.history_velocity_error);
  EXPECT_EQ(error_of("ours:\n  history_velocity_error: 2\n"), "c.yaml:2: ours.history_velocity_error must be true or false");
}

// Tracks, the lag window and what happens to a message later than it.
TEST(MethodConfigFile, ReadsOursTimeSettings) {
  const MethodConfig config =
      parse_method_config("c.yaml", "ours:\n  tracks: per-view\n  lag_window_s: 0.25\n  late_measurements: stop\n");
  EXPECT_TRUE(config.ours.per_view_tracks);
  EXPECT_EQ(config.ours.lag_window, 0.25);
  EXPECT_TRUE(config.ours.stop_on_late);
  EXPECT_FALSE(parse_method_config("c.yaml", "ours:\n  tracks: per-object\n").ours.per_view_tracks);
  EXPECT_EQ(error_of("ours:\n  tracks: per-camera\n"), "c.yaml:2: ours.tracks must be per-object or per-view");
  EXPECT_EQ(error_of("ours:\n  late_measurements: [stop]\n"),
            "c.yaml:2: ours.late_measurements must be leave-out or stop");
  EXPECT_EQ(error_of("ours:\n  lag_window_s: -1\n"), "c.yaml:2: ours.lag_window_s must be a finite number >= 0");
}

// Which motion a scene follows (core/motion_choice.hpp): the model, constant velocity where the
// innovations favour it (the default), or constant velocity always.
TEST(MethodConfigFile, ReadsTheMotionFallback) {
  EXPECT_EQ(MethodConfig{}.ours.motion_fallback, MotionFallback::kAuto);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  motion_fallback: off\n").ours.motion_fallback, MotionFallback::kOff);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  motion_fallback: always\n").ours.motion_fallback,
            MotionFallback::kAlways);
  EXPECT_EQ(parse_method_config("c.yaml", "ours:\n  motion_fallback: auto\n").ours.motion_fallback, MotionFallback::kAuto);
  EXPECT_EQ(error_of("ours:\n  adapt_process_noise: true\n  motion_fallback: sometimes\n"),
            "c.yaml:3: ours.motion_fallback must be auto, off or always");
}

}  // namespace
}  // namespace stgf

namespace stgf {
namespace {

// The χ² gate: off unless asked for; its probability in (0, 1).
TEST(MethodConfigFile, ReadsTheGateOfEachMethod) {
  const MethodConfig defaults = parse_method_config("c.yaml", "");
  EXPECT_FALSE(defaults.ours.gate.enabled);
  EXPECT_FALSE(defaults.wls_gate.enabled);
  EXPECT_FALSE(defaults.mmt_gate.enabled);
  const MethodConfig config = parse_method_config(
      "c.yaml", "wls:\n  gate: true\nmmt:\n  gate: true\n  gate_probability: 0.99\nours:\n  gate: true\n");
  EXPECT_TRUE(config.wls_gate.enabled);
  EXPECT_TRUE(config.mmt_gate.enabled);
  EXPECT_DOUBLE_EQ(config.mmt_gate.probability, 0.99);
  EXPECT_TRUE(config.ours.gate.enabled);
  EXPECT_EQ(error_of("ours:\n  gate_probability: 1.5\n"), "c.yaml:2: ours.gate_probability must be below 1 (e.g. 0.999)");
  EXPECT_EQ(error_of("wls:\n  gate: maybe\n"), "c.yaml:2: wls.gate must be true or false");
  EXPECT_EQ(error_of("wls:\n  gate_probability: 0\n"), "c.yaml:2: wls.gate_probability must be a finite number > 0");
  EXPECT_EQ(error_of("wls:\n  initial_position_variance: 1\n"), "c.yaml:2: unknown setting 'wls.initial_position_variance'");
}

}  // namespace
}  // namespace stgf
