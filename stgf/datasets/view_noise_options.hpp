// SPDX-License-Identifier: Apache-2.0
#pragma once
// Options that the synthetic and ethucy benchmarks share by name, meaning and rule (SyntheticOptions
// and EthUcyOptions document them): how their views are placed (angle jitter, sensor height, noise
// scale g) and the line-of-sight noise and misses the views measure with (synthetic.hpp,
// line_of_sight_noise and detection_probability). Both builders check and describe them here, so
// that the two cannot drift apart. `Options` is SyntheticOptions or EthUcyOptions.

#include <nlohmann/json.hpp>

#include "stgf/datasets/option_checks.hpp"

namespace stgf {

// Checks them in this order; the first one out of range is reported.
template <typename Options>
void check_view_noise_options(const OptionChecks& check, const Options& options) {
  check.not_negative("view_angle_jitter_rad", options.view_angle_jitter_rad);
  check.not_negative("min_sensor_height_m", options.min_sensor_height_m);
  check.not_negative("max_sensor_height_m", options.max_sensor_height_m);
  check.range("min_sensor_height_m", options.min_sensor_height_m, "max_sensor_height_m",
              options.max_sensor_height_m);
  check.positive("min_noise_scale", options.min_noise_scale);
  check.positive("max_noise_scale", options.max_noise_scale);
  check.range("min_noise_scale", options.min_noise_scale, "max_noise_scale", options.max_noise_scale);

  check.positive("range_noise_m", options.range_noise_m);
  check.not_negative("range_noise_per_m2", options.range_noise_per_m2);
  check.positive("cross_noise_m", options.cross_noise_m);
  check.not_negative("cross_noise_per_m", options.cross_noise_per_m);
  check.positive("vertical_noise_m", options.vertical_noise_m);
  check.not_negative("vertical_noise_per_m", options.vertical_noise_per_m);

  check.positive("max_range_m", options.max_range_m);
  check.probability("detection_probability_near", options.detection_probability_near);
  check.probability("detection_probability_far", options.detection_probability_far);
  check.range("detection_probability_far", options.detection_probability_far, "detection_probability_near",
              options.detection_probability_near);
}

// Their entries of benchmark.json's "options" (an object, to be merged into the builder's own).
template <typename Options>
nlohmann::json view_noise_options_json(const Options& options) {
  return {
      {"view_angle_jitter_rad", options.view_angle_jitter_rad},
      {"min_sensor_height_m", options.min_sensor_height_m},
      {"max_sensor_height_m", options.max_sensor_height_m},
      {"min_noise_scale", options.min_noise_scale},
      {"max_noise_scale", options.max_noise_scale},
      {"range_noise_m", options.range_noise_m},
      {"range_noise_per_m2", options.range_noise_per_m2},
      {"cross_noise_m", options.cross_noise_m},
      {"cross_noise_per_m", options.cross_noise_per_m},
      {"vertical_noise_m", options.vertical_noise_m},
      {"vertical_noise_per_m", options.vertical_noise_per_m},
      {"max_range_m", options.max_range_m},
      {"detection_probability_near", options.detection_probability_near},
      {"detection_probability_far", options.detection_probability_far},
  };
}

}  // namespace stgf
