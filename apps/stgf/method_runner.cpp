// SPDX-License-Identifier: Apache-2.0
#include "method_runner.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gating_log.hpp"
#include "stgf/model/general_model.hpp"
#include "stgf/model/registration_metadata.hpp"
#include "stgf/methods/filter_runner.hpp"

namespace stgf::cli {
namespace {

// The learned scales' quantiles outside which the prior in use does not fit the sensors: on the
// benchmarks' own validation splits with their own models the medians are 0.8–1.2, the 10th
// percentiles at least 0.47 and the 90th at most 2.3 (synchronous and asynchronous).
constexpr double kLowMedian = 0.5, kHighMedian = 2.0, kLowTenth = 0.2, kHighNinetieth = 4.0;

// κ̂_t and κ̂_n over the scenes (registration_prior_scale.hpp): how far the views' offsets were from the
// size the model's calibration expects, and, when the prior in use does not fit, a bound to set it to.
// `scenes`: which of the run's scenes these were ("" when all of them).
void log_registration_prior_scales(const std::string& method, const LearnedRegistrationScales& record,
                                   const std::string& scenes, const RegistrationPrior& prior,
                                   RegistrationScaleLearning learning) {
  const std::vector<RegistrationPriorScales>& learned = record.scales;
  const std::size_t without = record.scenes_without;
  // Lowered across scenes: the translations' scale only, or every scale (registration_scale_pool.hpp).
  const bool every_scale_lowered =
      RegistrationScalePool::lowering_for(prior.range_scale_sigma) == RegistrationScalePool::Use::kLowerOnly;
  if (!learned.empty()) {
    std::vector<double> translation, noise_ratio, along, across, vertical;
    for (const RegistrationPriorScales& scales : learned) {
      translation.push_back(scales.translation);
      noise_ratio.push_back(scales.noise_ratio);
      along.push_back(scales.along);
      across.push_back(scales.across);
      vertical.push_back(scales.vertical);
    }
    const auto at = [](const std::vector<double>& sorted, double q) {
      return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5)];
    };
    std::sort(translation.begin(), translation.end());
    std::sort(noise_ratio.begin(), noise_ratio.end());
    std::sort(along.begin(), along.end());
    std::sort(across.begin(), across.end());
    std::sort(vertical.begin(), vertical.end());
    const auto quantiles = [&at](const std::vector<double>& sorted) {
      return fmt::format("median {:.2f} (10-90 %: {:.2f}-{:.2f})", at(sorted, 0.5), at(sorted, 0.1), at(sorted, 0.9));
    };
    spdlog::info(
        "{}: registration prior scaled {} from the views' disagreements over {} scene(s){}: translation "
        "κ_t {}, offset in units of the noise κ_n {} (along the rays κ_a {}, across them κ_c {}){}; the "
        "offsets' σ is √κ times the model's calibration",
        method,
        learning == RegistrationScaleLearning::kAcrossScenes ? "across scenes"
        : learning == RegistrationScaleLearning::kPerScene   ? "per scene"
        : every_scale_lowered
            ? "per scene (each from the run's scales where these are below the calibration's)"
            : "per scene (each from the run's scales, the translations' only where below the calibration's)",
        learned.size(), scenes, quantiles(translation), quantiles(noise_ratio), quantiles(along),
        quantiles(across),
        prior.translation_sigma.z() == 0.0 && prior.noise_ratio.z() == 0.0
            ? std::string()
            : fmt::format(", vertical offsets κ_v {}", quantiles(vertical)));
    if (record.common_translation_raised > 0) {
      spdlog::info(
          "{}: the offset common to the views, which no disagreement shows, reported at the size the scenes "
          "before gave it (κ_t {:.2f}, their median) wherever a scene's own was lower (before it had learned "
          "one, or after): {} of {} scene(s){}",
          method, record.common_translation_run_scale.value_or(0.0), record.common_translation_raised,
          learned.size() + without, scenes);
    }
    // Each scene's scales are held near 1 by its prior; many scenes far from 1 in one direction say
    // that the prior itself is off for these sensors.
    const auto direction = [&at](const std::vector<double>& sorted) {
      if (at(sorted, 0.5) >= kHighMedian || at(sorted, 0.9) >= kHighNinetieth) return 1;
      if (at(sorted, 0.5) <= kLowMedian || at(sorted, 0.1) <= kLowTenth) return -1;
      return 0;
    };
    const int t = prior.translation_sigma.isZero() ? 0 : direction(translation);
    const int n = prior.noise_ratio.isZero() && prior.range_scale_sigma == 0.0 ? 0 : direction(noise_ratio);
    if (t != 0 || n != 0) {
      const double kt = std::sqrt(at(translation, 0.5)), kn = std::sqrt(at(noise_ratio, 0.5)),
                   kv = std::sqrt(at(vertical, 0.5)), ka = std::sqrt(at(along, 0.5)),
                   kc = std::sqrt(at(across, 0.5));  // each axis group's own scale
      const auto bound = [](int d) { return d > 0 ? "at least" : "at most"; };
      std::string suggestion;
      if (t != 0) {
        suggestion += fmt::format("registration_translation_sigma_m {} [{:.3g}, {:.3g}, {:.3g}]", bound(t),
                                  prior.translation_sigma.x() * kt, prior.translation_sigma.y() * kt,
                                  prior.translation_sigma.z() * kv);
      }
      if (n != 0 && !prior.noise_ratio.isZero()) {
        const Vector3d ratio = prior.noise_ratio.cwiseProduct(Vector3d(ka, kc, kv));
        suggestion += fmt::format("{}registration_noise_ratio {} ", suggestion.empty() ? "" : ", ", bound(n));
        suggestion += ratio.isConstant(ratio.x()) ? fmt::format("{:.3g}", ratio.x())
                                                  : fmt::format("[{:.3g}, {:.3g}, {:.3g}]", ratio.x(), ratio.y(), ratio.z());
      }
      if (n != 0 && prior.range_scale_sigma > 0.0) {
        suggestion += fmt::format("{}registration_range_scale_sigma {} {:.3g}", suggestion.empty() ? "" : ", ", bound(n),
                                  prior.range_scale_sigma * kn);
      }
      spdlog::info(
          "{}: these views' offsets do not fit the registration prior in use: {} If you know your "
          "sensors' registration error, set it under `ours:` in --config; these scenes suggest {}",
          method,
          learning == RegistrationScaleLearning::kAcrossScenes
              ? "each scene starts from what the scenes before it showed and learns on from its own; the "
                "first ones, with few before them, stay nearer the prior's."
          : learning == RegistrationScaleLearning::kPerScene
              ? "each scene learns its own scale, but only within a few times of the prior's, and a short "
                "scene less (`registration_prior_scale: shrink-across-scenes` or `across-scenes` pools the "
                "scenes)."
          : every_scale_lowered
              ? "each scene learns its own scale within a few times of where it starts, and a short scene "
                "less; the run's scenes together lower that start where they show smaller offsets than the "
                "calibration, never raise it (`registration_prior_scale: across-scenes` would)."
              : "each scene learns its own scale within a few times of where it starts, and a short scene "
                "less; the run's scenes together set that start, the translations' only where lower than the "
                "calibration's (`registration_prior_scale: across-scenes` raises them too).",
          suggestion);
    }
  }
  if (without > 0) {
    spdlog::info("{}: {} scene(s){} kept the registration prior as calibrated: their views seldom measured an object "
                 "at the same time, too little to learn its scale from (set it under `ours:` in --config if your "
                 "sensors are registered differently)",
                 method, without, scenes);
  }
}

}  // namespace

void log_method_report(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                       const std::string& model_path, const MethodRunReport& report) {
  if (report.registration_missing) {
    spdlog::warn("{} holds no registration calibration (trained before stgf calibrated it); the views' offsets are "
                 "taken as zero unless set under `ours:` in --config",
                 model_path);
  }
  if (report.restarted_tracks > report.gating.restarts) {
    if (model->coasting_horizon() > model->prediction_horizon()) {
      spdlog::info("{}: {} track(s) started again: the object had not been seen for longer than the {:.2f} s that "
                   "the model's Q was calibrated to coast across (twice the longest interval it was calibrated at), nor "
                   "for longer than 2.5 of its own frame intervals (one missed frame)",
                   method, report.restarted_tracks - report.gating.restarts, model->coasting_horizon());
    } else {
      spdlog::info("{}: {} track(s) started again: the object had not been seen for longer than the model's horizon "
                   "of {:.2f} s (twice the longest interval it trained on; a model trained with `stgf train "
                   "--long-intervals` above 0, the default, has Q calibrated for tracks to coast further by constant "
                   "velocity)",
                   method, report.restarted_tracks - report.gating.restarts, model->prediction_horizon());
    }
  }
  if (report.coasting_predictions > 0) {
    spdlog::info("{}: {} prediction(s) by constant velocity with the model's coasting Q: the object unseen for longer "
                 "than the model's horizon of {:.2f} s, or its history spaced wider than {:.2f} s (where the model's "
                 "calibration hands its forecasts over to constant velocity)",
                 method, report.coasting_predictions, model->prediction_horizon(), model->widest_history_spacing());
  }
  log_gating(method, config.ours.gate, report.gating);
  const MotionChoiceSummary& choice = report.motion_choice;
  if (config.ours.motion_fallback == MotionFallback::kAuto && choice.switched_scenes > 0) {
    spdlog::info("{}: constant velocity predicted better than the model in {} of {} scene(s), which followed it from "
                 "then on ({} of them went back to the model); `motion_fallback: off` under `ours:` in --config "
                 "keeps the model",
                 method, choice.switched_scenes, choice.scenes, choice.switched_scenes - choice.constant_velocity_scenes);
  }
  if (const auto& scales = report.process_noise_scales_across_scenes) {
    std::string learned;
    const auto add = [&learned](const char* what, const std::optional<Vector3d>& scale) {
      if (!scale) return;
      learned += fmt::format("{}{} ({:.3g}, {:.3g}, {:.3g})", learned.empty() ? "" : ", ", what, scale->x(), scale->y(),
                             scale->z());
    };
    add("the model's", scales->followed);
    add("constant velocity's", scales->fallback);
    add("the coasting tracks'", scales->coasting);
    if (!learned.empty()) {
      spdlog::info("{}: Q scaled across scenes from the innovations, λ per axis (x, y, z): {} (each scene starts from "
                   "the scenes before it and learns on from its own)",
                   method, learned);
    }
  }
  // Only `ours` learns the scales, and it has a model. Scenes of fixed and of moving sensors apart
  // (their scales may be learned differently: registration_scale_learning_for), named so where the run
  // had scenes whose sensors move.
  const auto had_scenes = [](const LearnedRegistrationScales& record) {
    return !record.scales.empty() || record.scenes_without > 0;
  };
  const bool moving = had_scenes(report.registration_prior_scales.moving);
  const bool any = moving || had_scenes(report.registration_prior_scales.fixed);
  const RegistrationPrior prior =
      any && model != nullptr ? resolve_registration_prior(config.ours, model->metadata(), model_path) : RegistrationPrior{};
  for (SensorMotion sensors : kSensorMotions) {
    const LearnedRegistrationScales& record = report.registration_prior_scales[sensors];
    if (!had_scenes(record) || model == nullptr) continue;
    log_registration_prior_scales(method, record,
                                  sensors == SensorMotion::kMoving ? " whose sensors move"
                                  : moving                         ? " whose sensors stand still"
                                                                   : "",
                                  prior, report.registration_scale_learning[sensors]);
  }
  if (report.late_rows > 0) {
    spdlog::info("{}: {} late row(s) fused in their place in time (arrived after later ones, within the lag window "
                 "of {} s; the scenes went back {} time(s) for them)",
                 method, report.late_rows, config.ours.lag_window, report.rewinds);
  }
  if (report.late_measurements > 0) {
    spdlog::warn("{}: {} row(s) arrived more than the lag window of {} s late and were left out of the fusion "
                 "(each row's estimate is its own measurement)",
                 method, report.late_measurements, config.ours.lag_window);
  }
}

std::vector<Gaussian3> run_method_and_log(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                                          const std::string& model_path, std::span<const Measurement> rows) {
  MethodRunReport report;
  std::vector<Gaussian3> estimates = run_named_method(method, config, model, model_path, rows, &report);
  log_method_report(method, config, model, model_path, report);
  return estimates;
}

namespace {

// The model is loaded before the file is read; the NamedMethodRun takes the file block by block.
class LoadedMethod final : public BlockMethod {
 public:
  LoadedMethod(std::string method, MethodConfig config, std::string model_path)
      : method_(std::move(method)),
        config_(std::move(config)),
        model_(load_model_for(method_, model_path)),
        model_name_(model_path.empty() ? kGeneralModelName : std::move(model_path)),
        run_(method_, config_, &model_, model_name_) {
    if (model_name_ == kGeneralModelName) {
      spdlog::info("{}: no --model given: {}, trained on pedestrians and vehicles of PETS 2009, ETH/UCY and KITTI "
                   "(models/README.md); a model trained on your own sensors' data (stgf train) fits them better",
                   method_, kGeneralModelName);
    }
  }

  std::size_t scenes_per_block() const override { return method_ == "sttp" ? 1 : kScenesPerFilterBlock; }
  std::vector<Gaussian3> add(std::span<const Measurement> rows) override { return run_.add(rows); }
  std::vector<Gaussian3> finish() override { return run_.finish(); }
  void log_report() const override { log_method_report(method_, config_, &model_, model_name_, run_.report()); }

 private:
  std::string method_;
  MethodConfig config_;
  TrainedMotionModel model_;
  std::string model_name_;  // its path, or the general model's name
  NamedMethodRun run_;
};

}  // namespace

std::unique_ptr<BlockMethod> prepare_learned_method(const std::string& method, const MethodConfig& config,
                                                    const std::string& model_path) {
  return std::make_unique<LoadedMethod>(method, config, model_path);
}

}  // namespace stgf::cli
