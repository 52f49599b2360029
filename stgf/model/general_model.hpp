// SPDX-License-Identifier: Apache-2.0
#pragma once
// The general model shipped with stgf: Φ trained on all the real motion the project has (PETS 2009
// pedestrians at 7 Hz seen by cameras, KITTI vehicles at 10 Hz seen by connected vehicles, ETH/UCY
// pedestrians at 2.5 Hz), with its Q and registration prior calibrated on their validation splits.
// It is what `stgf run --method ours` (and ours-l) use without --model, and the Python module's
// stgf.general_model(): a user with no ground truth to train on starts from it.
//
// The file is models/general.pt, built into the library (cmake/embed_file.cmake), so nothing is
// looked up on disk. Its recipe, its training data and their terms (KITTI's are non-commercial, and a
// model trained on it inherits them), and the validation numbers it must keep (tested) are in
// models/README.md. A model trained on the user's own sensors (stgf train) fits them better: on
// data unlike all three, the filter's online scales (Q's λ, the registration prior's κ_t, κ_n)
// are what keep its covariance honest.

#include <string_view>

#include "stgf/model/trained_motion_model.hpp"

namespace stgf {

// How messages name it.
inline constexpr const char* kGeneralModelName = "stgf's general model (models/general.pt)";

// The bytes of models/general.pt; empty in a build with -DSTGF_GENERAL_MODEL=OFF (its terms are
// KITTI's, non-commercial: models/README.md).
std::string_view general_model_bytes();

// The model, read from those bytes and checked as any model file is; std::invalid_argument in a build
// without it.
TrainedMotionModel general_model();

}  // namespace stgf
