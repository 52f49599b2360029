// SPDX-License-Identifier: Apache-2.0
#pragma once
// Methods by name, as the CLI's `--method` knows them.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stgf/core/constant_velocity_filter.hpp"
#include "stgf/core/measurement_gate.hpp"
#include "stgf/core/motion_choice.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

// Where `ours` learns the registration prior's scales κ_t, κ_n (core/registration_prior_scale.hpp):
// each scene alone; the run's scenes pooled, every scene starting from the earlier scenes' evidence
// and learning on from its own; or the pool lowering a scale where its estimate is below the
// calibration's, each scene learning its own from there
// (core/registration_scale_pool.hpp, design §1.7).
enum class RegistrationScaleLearning { kPerScene, kAcrossScenes, kShrinkAcrossScenes };
// Where Q's scales λ are learned (process_noise_pool.hpp): each scene alone (λ ≥ 1); the run's scenes
// pooled, every scene starting from the earlier scenes' evidence, λ below 1 too; or pooled with λ held
// at 1 and above (Q at least as calibrated).
enum class ProcessNoiseScaleLearning { kPerScene, kAcrossScenes, kGrowAcrossScenes };

// `ours`: how it accounts for the views' registration error (core/view_registration.hpp) and for a
// Q that does not fit the data (core/process_noise_scale.hpp).
struct OursSettings {
  bool registration = true;                   // estimate each view's offset and keep its uncertainty
  std::optional<Vector3d> translation_sigma;  // σ of the translation offset (m); unset: the model's calibration
  std::optional<Vector3d> noise_ratio;        // α along, across, vertical to each ray; unset: the model's calibration
  std::optional<double> range_scale_sigma;    // σ_ε of each view's range scale; unset: the model's calibration
  bool adapt_process_noise = true;            // scale Q online from the innovations
  // ... per scene or pooled over the run's scenes (process_noise_pool.hpp); unset (auto):
  // process_noise_scale_learning_for.
  std::optional<ProcessNoiseScaleLearning> process_noise_scale_learning;
  MotionFallback motion_fallback = MotionFallback::kAuto;  // constant velocity where it predicts better
  bool adapt_registration_prior = true;       // scale the registration prior from the views' disagreements
  bool cross_view_weights = true;  // down-weight a measurement the other views at its time place far off
  bool history_velocity_error = true;  // a forecast's covariance counts its history's velocity error
  // Unset (auto): kAcrossScenes where the sensors move; where they stand still kShrinkAcrossScenes for
  // a model trained on several benchmarks, kPerScene for a model of one (registration_scale_learning_for).
  std::optional<RegistrationScaleLearning> registration_scale_learning;
  bool per_view_tracks = false;               // the paper's per-view tracks instead of one per object
  double lag_window = 1.0;                    // s: how late a message may arrive and still be fused in place
  bool stop_on_late = false;                  // a message later than that: stop (true) or leave it out
  GateOptions gate;                           // the χ² gate and the views' noise scales (off)
};

// Settings of every method, read from the YAML config (see config/methods.yaml).
struct MethodConfig {
  ConstantVelocityModel mmt;
  OursSettings ours;
  GateOptions mmt_gate;  // the baselines' χ² gate (off)
  GateOptions wls_gate;
};

// The names `make_localizer` accepts, in the order tables list them.
const std::vector<std::string>& method_names();

// Every method `stgf run` knows, in the order tables list them: aom, wls, mmt (model-free, above)
// and sttp, ours-l, ours (they need the learned motion model: stgf/model/named_methods.hpp).
const std::vector<std::string>& all_method_names();
bool is_learned_method(const std::string& name);

// A fresh localizer for one scene. Throws std::invalid_argument for an unknown name.
std::unique_ptr<Localizer> make_localizer(const std::string& name, const MethodConfig& config);

}  // namespace stgf
