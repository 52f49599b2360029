// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/registration_metadata.hpp"

#include <cmath>

#include "stgf/io/input_error.hpp"

namespace stgf {

nlohmann::json registration_prior_to_json(const RegistrationPrior& prior) {
  return {{"translation_sigma_m",
           {prior.translation_sigma.x(), prior.translation_sigma.y(), prior.translation_sigma.z()}},
          {"noise_ratio", prior.noise_ratio}};
}

std::optional<RegistrationPrior> registration_prior_from_metadata(const nlohmann::json& metadata,
                                                                  const std::string& path) {
  if (!metadata.is_object() || !metadata.contains("registration")) return std::nullopt;
  const nlohmann::json& entry = metadata.at("registration");
  auto finite_non_negative = [](const nlohmann::json& value) {
    return value.is_number() && std::isfinite(value.get<double>()) && value.get<double>() >= 0.0;
  };
  const bool valid = entry.is_object() && entry.contains("translation_sigma_m") && entry.contains("noise_ratio") &&
                     entry.at("translation_sigma_m").is_array() && entry.at("translation_sigma_m").size() == 3 &&
                     finite_non_negative(entry.at("translation_sigma_m")[0]) &&
                     finite_non_negative(entry.at("translation_sigma_m")[1]) &&
                     finite_non_negative(entry.at("translation_sigma_m")[2]) && finite_non_negative(entry.at("noise_ratio"));
  if (!valid) {
    throw InputError(path, 0, "malformed registration calibration in the model metadata (want translation_sigma_m: "
                              "[3 numbers >= 0], noise_ratio: number >= 0)");
  }
  RegistrationPrior prior;
  const nlohmann::json& sigma = entry.at("translation_sigma_m");
  prior.translation_sigma = Vector3d(sigma[0].get<double>(), sigma[1].get<double>(), sigma[2].get<double>());
  prior.noise_ratio = entry.at("noise_ratio").get<double>();
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
  if (missing != nullptr) *missing = !calibrated && !(settings.translation_sigma && settings.noise_ratio);
  return prior;
}

}  // namespace stgf
