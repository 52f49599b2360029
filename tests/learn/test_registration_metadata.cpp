// SPDX-License-Identifier: Apache-2.0
// The registration prior in a model file's metadata (model/registration_metadata.hpp): round trip,
// absent, malformed; and the prior `ours` runs with once the config's settings are applied.

#include <gtest/gtest.h>

#include "stgf/model/registration_metadata.hpp"
#include "support/input_errors.hpp"

namespace stgf {
namespace {

using testing::expect_input_error;

RegistrationPrior calibrated_prior() {
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.2, 0.05);
  prior.noise_ratio = Vector3d::Constant(0.7);
  return prior;
}

nlohmann::json metadata_with(const RegistrationPrior& prior) {
  return {{"trained_on", "mpl"}, {"registration", registration_prior_to_json(prior)}};
}

TEST(RegistrationMetadata, RoundTrip) {
  const nlohmann::json metadata = metadata_with(calibrated_prior());
  // Through text, as the model file stores it.
  const nlohmann::json reread = nlohmann::json::parse(metadata.dump());
  const std::optional<RegistrationPrior> prior = registration_prior_from_metadata(reread, "m.pt");
  ASSERT_TRUE(prior.has_value());
  EXPECT_EQ(prior->translation_sigma, calibrated_prior().translation_sigma);
  EXPECT_EQ(prior->noise_ratio, calibrated_prior().noise_ratio);
  EXPECT_EQ(reread.at("registration").at("translation_sigma_m").size(), 3u);
  EXPECT_EQ(prior->range_scale_sigma, 0.0);
  EXPECT_FALSE(reread.at("registration").contains("range_scale_sigma"));  // none: the file as before it existed
}

// A range scale is written and read back; one that is negative or not a number is malformed.
TEST(RegistrationMetadata, RangeScaleRoundTrip) {
  RegistrationPrior scaled = calibrated_prior();
  scaled.range_scale_sigma = 0.0083;
  const nlohmann::json reread = nlohmann::json::parse(metadata_with(scaled).dump());
  EXPECT_EQ(reread.at("registration").at("range_scale_sigma").get<double>(), 0.0083);
  EXPECT_EQ(registration_prior_from_metadata(reread, "m.pt")->range_scale_sigma, 0.0083);
  for (const nlohmann::json& bad : {nlohmann::json(-0.01), nlohmann::json("wide")}) {
    nlohmann::json metadata = reread;
    metadata["registration"]["range_scale_sigma"] = bad;
    expect_input_error([&] { registration_prior_from_metadata(metadata, "models/m.pt"); }, "models/m.pt", 0);
  }
  // A setting overrides the calibration, as σ and α do.
  OursSettings settings;
  settings.range_scale_sigma = 0.02;
  EXPECT_EQ(resolve_registration_prior(settings, reread, "m.pt").range_scale_sigma, 0.02);
  EXPECT_EQ(resolve_registration_prior(OursSettings{}, reread, "m.pt").range_scale_sigma, 0.0083);
}

// The kind of sensors the calibration's data had is written and read back; none (both kinds, or a
// model from before it was recorded) is left out; another value is malformed.
TEST(RegistrationMetadata, CalibratedSensorsRoundTrip) {
  EXPECT_FALSE(registration_prior_from_metadata(metadata_with(calibrated_prior()), "m.pt")->calibrated_sensors);
  EXPECT_FALSE(metadata_with(calibrated_prior()).at("registration").contains("sensors"));
  for (const SensorMotion kind : kSensorMotions) {
    RegistrationPrior prior = calibrated_prior();
    prior.calibrated_sensors = kind;
    const nlohmann::json reread = nlohmann::json::parse(metadata_with(prior).dump());
    EXPECT_EQ(reread.at("registration").at("sensors").get<std::string>(), kind == SensorMotion::kFixed ? "fixed" : "moving");
    EXPECT_EQ(registration_prior_from_metadata(reread, "m.pt")->calibrated_sensors, kind);
    EXPECT_EQ(resolve_registration_prior(OursSettings{}, reread, "m.pt").calibrated_sensors, kind);
  }
  for (const nlohmann::json& bad : {nlohmann::json("parked"), nlohmann::json(1)}) {
    nlohmann::json metadata = metadata_with(calibrated_prior());
    metadata["registration"]["sensors"] = bad;
    expect_input_error([&] { registration_prior_from_metadata(metadata, "models/m.pt"); }, "models/m.pt", 0);
  }
}

TEST(RegistrationMetadata, MissingCalibrationIsNullopt) {
  EXPECT_FALSE(registration_prior_from_metadata(nlohmann::json::object(), "m.pt").has_value());
  EXPECT_FALSE(registration_prior_from_metadata({{"trained_on", "mpl"}}, "m.pt").has_value());
  EXPECT_FALSE(registration_prior_from_metadata(nlohmann::json(), "m.pt").has_value());  // no metadata at all
}

TEST(RegistrationMetadata, MalformedCalibrationNamesTheFile) {
  const nlohmann::json good = registration_prior_to_json(calibrated_prior());
  std::vector<nlohmann::json> malformed;
  malformed.push_back(5);
  malformed.push_back(nlohmann::json::object());
  {
    nlohmann::json entry = good;
    entry["translation_sigma_m"] = {0.3, 0.2};
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry["translation_sigma_m"] = {0.3, -0.2, 0.1};
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry["translation_sigma_m"] = {0.3, "wide", 0.1};
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry["translation_sigma_m"] = 0.3;
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry["noise_ratio"] = -1.0;
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry["noise_ratio"] = "0.5";
    malformed.push_back(entry);
  }
  {
    nlohmann::json entry = good;
    entry.erase("noise_ratio");
    malformed.push_back(entry);
  }
  for (const nlohmann::json& entry : malformed) {
    const nlohmann::json metadata = {{"registration", entry}};
    const std::string message = expect_input_error(
        [&] { registration_prior_from_metadata(metadata, "models/m.pt"); }, "models/m.pt", 0);
    EXPECT_NE(message.find("registration"), std::string::npos) << entry.dump();
  }
}

TEST(RegistrationMetadata, RegistrationOffGivesTheZeroPrior) {
  OursSettings settings;
  settings.registration = false;
  settings.translation_sigma = Vector3d::Constant(1.0);
  settings.noise_ratio = Vector3d::Constant(2.0);
  bool missing = true;
  const RegistrationPrior prior =
      resolve_registration_prior(settings, metadata_with(calibrated_prior()), "m.pt", &missing);
  EXPECT_TRUE(prior.is_zero());
  EXPECT_FALSE(missing);
}

TEST(RegistrationMetadata, CalibrationIsUsedAndOverridesApply) {
  const nlohmann::json metadata = metadata_with(calibrated_prior());
  bool missing = true;
  {
    const RegistrationPrior prior = resolve_registration_prior(OursSettings{}, metadata, "m.pt", &missing);
    EXPECT_EQ(prior.translation_sigma, calibrated_prior().translation_sigma);
    EXPECT_EQ(prior.noise_ratio, calibrated_prior().noise_ratio);
    EXPECT_FALSE(missing);
  }
  {
    OursSettings settings;
    settings.translation_sigma = Vector3d(1.0, 2.0, 3.0);
    missing = true;
    const RegistrationPrior prior = resolve_registration_prior(settings, metadata, "m.pt", &missing);
    EXPECT_EQ(prior.translation_sigma, Vector3d(1.0, 2.0, 3.0));
    EXPECT_EQ(prior.noise_ratio, calibrated_prior().noise_ratio);
    EXPECT_FALSE(missing);
  }
  {
    OursSettings settings;
    settings.noise_ratio = Vector3d::Constant(0.0);
    missing = true;
    const RegistrationPrior prior = resolve_registration_prior(settings, metadata, "m.pt", &missing);
    EXPECT_EQ(prior.translation_sigma, calibrated_prior().translation_sigma);
    EXPECT_EQ(prior.noise_ratio, Vector3d::Zero());
    EXPECT_FALSE(missing);
  }
}

TEST(RegistrationMetadata, MissingWhenNeitherCalibratedNorFullySet) {
  const nlohmann::json uncalibrated = {{"trained_on", "mpl"}};
  bool missing = false;
  {
    const RegistrationPrior prior =
        resolve_registration_prior(OursSettings{}, uncalibrated, "m.pt", &missing);
    EXPECT_TRUE(prior.is_zero());
    EXPECT_TRUE(missing);
  }
  {
    OursSettings settings;
    settings.translation_sigma = Vector3d(0.5, 0.5, 0.1);
    missing = false;
    const RegistrationPrior prior = resolve_registration_prior(settings, uncalibrated, "m.pt", &missing);
    EXPECT_EQ(prior.translation_sigma, Vector3d(0.5, 0.5, 0.1));
    EXPECT_EQ(prior.noise_ratio, Vector3d::Zero());
    EXPECT_TRUE(missing);
  }
  {
    OursSettings settings;
    settings.translation_sigma = Vector3d(0.5, 0.5, 0.1);
    settings.noise_ratio = Vector3d::Constant(0.3);
    missing = true;
    const RegistrationPrior prior = resolve_registration_prior(settings, uncalibrated, "m.pt", &missing);
    EXPECT_EQ(prior.translation_sigma, Vector3d(0.5, 0.5, 0.1));
    EXPECT_EQ(prior.noise_ratio, Vector3d::Constant(0.3));
    EXPECT_FALSE(missing);
  }
  // `missing` is optional.
  EXPECT_TRUE(resolve_registration_prior(OursSettings{}, uncalibrated, "m.pt").is_zero());
  // A malformed calibration is an error, not a silent zero.
  const nlohmann::json malformed = {{"registration", {{"noise_ratio", 1.0}}}};
  expect_input_error([&] { resolve_registration_prior(OursSettings{}, malformed, "m.pt", &missing); }, "m.pt",
                     0);
}

}  // namespace
}  // namespace stgf
