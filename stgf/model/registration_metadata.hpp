// SPDX-License-Identifier: Apache-2.0
#pragma once
// The registration prior (core/view_registration.hpp) as stored in a model file's metadata, next to
// the Q it was calibrated with (both from the validation split of the training benchmark):
//   "registration": {"translation_sigma_m": [σx, σy, σz], "noise_ratio": α, "calibrated_on": "..."}
// "noise_ratio" is one number when α is the same along, across and vertical to each ray (every
// model before α per axis, and so read), else [α_along, α_across, α_vertical]. "range_scale_sigma": σ_ε,
// only when the model was calibrated with one (`stgf train --range-scale`); without it, none.
// "sensors": "fixed" or "moving", the kind of sensors the calibration's data had where all were of one
// kind (view_registration.hpp's calibrated_sensors); without it (both kinds, or a model from before it
// was recorded), none.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "stgf/core/view_registration.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf {

nlohmann::json registration_prior_to_json(const RegistrationPrior& prior);

// nullopt when the metadata holds no calibration (a model from before it existed); InputError
// naming `path` when it holds a malformed one.
std::optional<RegistrationPrior> registration_prior_from_metadata(const nlohmann::json& metadata,
                                                                  const std::string& path);

}  // namespace stgf

namespace stgf {

// The prior `ours` runs with: zero when settings.registration is off; otherwise the model's
// calibration with the settings' overrides applied. When a part is neither calibrated nor set,
// it is zero and `missing` (if given) is set.
RegistrationPrior resolve_registration_prior(const OursSettings& settings, const nlohmann::json& metadata,
                                             const std::string& model_path, bool* missing = nullptr);

}  // namespace stgf
