// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/registration_metadata.hpp"

#include <cmath>

#include "stgf/io/input_error.hpp"

namespace stgf {

nlohmann::json registration_prior_to_json(const RegistrationPrior& prior) {
  nlohmann::json entry = {{"translation_sigma_m",
           {prior.translation_sigma.x(), prior.translation_sigma.y(), prior.translation_sigma.z()}},
          {"noise_ratio", prior.noise_ratio.isConstant(prior.noise_ratio.x())
                              ? nlohmann::json(prior.noise_ratio.x())
                              : nlohmann::json{prior.noise_ratio.x(), prior.noise_ratio.y(), prior.noise_ratio.z()}}};
  // Written only when there is one, so that a model calibrated without it is the file it was before.
  if (prior.range_scale_sigma > 0.0) entry["range_scale_sigma"] = prior.range_scale_sigma;
  if (prior.calibrated_sensors) {
    entry["sensors"] = *prior.calibrated_sensors == SensorMotion::kMoving ? "moving" : "fixed";
  }
  return entry;
}

std::optional<RegistrationPrior> registration_prior_from_metadata(const nlohmann::json& metadata,
                                                                  const std::string& path) {
  if (!metadata.is_object() || !metadata.contains("registration")) return std::nullopt;
  const nlohmann::json& entry = metadata.at("registration");
  auto finite_non_negative = [](const nlohmann::json& value) {
    return value.is_number() && std::isfinite(value.get<double>()) && value.get<double>() >= 0.0;
  };
  auto three_finite_non_negative = [&](const nlohmann::json& value) {
    return value.is_array() && value.size() == 3 && finite_non_negative(value[0]) && finite_non_negative(value[1]) &&
           finite_non_negative(value[2]);
  };
  const bool valid = entry.is_object() && entry.contains("translation_sigma_m") && entry.contains("noise_ratio") &&
                     three_finite_non_negative(entry.at("translation_sigma_m")) &&
                     (finite_non_negative(entry.at("noise_ratio")) || three_finite_non_negative(entry.at("noise_ratio"))) &&
                     (!entry.contains("range_scale_sigma") || finite_non_negative(entry.at("range_scale_sigma"))) &&
                     (!entry.contains("sensors") || entry.at("sensors") == "fixed" || entry.at("sensors") == "moving");
  if (!valid) {
    throw InputError(path, 0, "malformed registration calibration in the model metadata (want translation_sigma_m: "
                              "[3 numbers >= 0], noise_ratio: number >= 0 or [3 numbers >= 0], range_scale_sigma: "
                              "number >= 0 if given, sensors: \"fixed\" or \"moving\" if given)");
  }
  RegistrationPrior prior;
  const nlohmann::json& sigma = entry.at("translation_sigma_m");
  prior.translation_sigma = Vector3d(sigma[0].get<double>(), sigma[1].get<double>(), sigma[2].get<double>());
  const nlohmann::json& ratio = entry.at("noise_ratio");
  prior.noise_ratio = ratio.is_array() ? Vector3d(ratio[0].get<double>(), ratio[1].get<double>(), ratio[2].get<double>())
                                       : Vector3d::Constant(ratio.get<double>());
  prior.range_scale_sigma = entry.value("range_scale_sigma", 0.0);  // none: calibrated without one
  if (entry.contains("sensors")) {  // none: sensors of both kinds, or a model from before it was recorded
    prior.calibrated_sensors = entry.at("sensors") == "moving" ? SensorMotion::kMoving : SensorMotion::kFixed;
  }
  return prior;
}

RegistrationPrior resolve_registration_prior(const OursSettings& settings, const nlohmann::json& metadata,
                                             const std::string& model_path, bool* missing) {
  if (missing != nullptr) *missing = false;
  if (!settings.registration) return {};
  const std::optional<RegistrationPrior> calibrated = registration_prior_from_metadata(metadata, model_path);
  RegistrationPrior prior = calibrated.value_or(RegistrationPrior{});
  if (settings.translation_sigma) prior.translation_sigma = *settings.translation_sigma;
  if (settings.noise_ratio) prior.noise_ratio = *settings.noise_ratio;
  if (settings.range_scale_sigma) prior.range_scale_sigma = *settings.range_scale_sigma;
  if (missing != nullptr) *missing = !calibrated && !(settings.translation_sigma && settings.noise_ratio);
  return prior;
}

}  // namespace stgf
