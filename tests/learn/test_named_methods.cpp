// SPDX-License-Identifier: Apache-2.0
// A method given a list in parts of whole scenes (NamedMethodRun, as `stgf run` gives it a file a block
// of scenes at a time) gives the estimates of one run over the whole list, bit for bit: Φ's batched
// passes see the same graphs. With more scenes than one block of the filter runner, and more graphs
// than one forward pass of sttp, so that the parts' boundaries fall inside the batching.

#include "stgf/model/named_methods.hpp"

#include <algorithm>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "stgf/datasets/synthetic.hpp"
#include "stgf/io/method_config_file.hpp"
#include "stgf/model/learned_methods.hpp"
#include "stgf/model/motion_graphs.hpp"
#include "stgf/methods/filter_runner.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf {
namespace {

// 300 scenes (more than kScenesPerFilterBlock = 16, and than 256) of 2 objects seen by 3 views over 8 steps: 6300
// sttp graphs (more than one forward pass of 4096).
const std::vector<Measurement>& many_scenes() {
  static const std::vector<Measurement> rows = [] {
    SyntheticOptions options;
    options.seed = 9;
    options.scenes = 300;
    options.objects = 2;
    options.views = 3;
    options.steps = 8;
    return make_synthetic_benchmark(options).test.measurements;
  }();
  return rows;
}

// The list cut into parts of `scenes` whole scenes each (the last one shorter).
std::vector<std::span<const Measurement>> parts_of(std::span<const Measurement> rows, std::size_t scenes) {
  std::vector<std::span<const Measurement>> parts;
  std::size_t first = 0;
  std::size_t in_part = 0;
  for (std::size_t k = 1; k <= rows.size(); ++k) {
    if (k < rows.size() && rows[k].scene == rows[k - 1].scene) continue;
    if (++in_part == scenes || k == rows.size()) {
      parts.push_back(rows.subspan(first, k - first));
      first = k;
      in_part = 0;
    }
  }
  return parts;
}

const TrainedMotionModel& model() {
  static const TrainedMotionModel trained = [] {
    MotionModelShape shape;
    shape.history_length = 4;
    return MotionModel(shape, MotionNormalisation{1.2, 0.1, 5.0, 0.1}, 7).trained();
  }();
  return trained;
}

void expect_identical(const std::vector<Gaussian3>& a, const std::vector<Gaussian3>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t differing = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].mean() != b[k].mean() || a[k].covariance() != b[k].covariance()) ++differing;
  }
  EXPECT_EQ(differing, 0u) << what << ": rows whose estimate is not bit for bit the whole run's";
}

std::vector<Gaussian3> in_parts(const std::string& method, std::size_t scenes_per_part, MethodRunReport& report,
                                const MethodConfig& config = MethodConfig{}) {
  NamedMethodRun run(method, config, &model(), "model.pt");
  std::vector<Gaussian3> estimates;
  for (std::span<const Measurement> part : parts_of(many_scenes(), scenes_per_part)) {
    const std::vector<Gaussian3> now = run.add(part);
    estimates.insert(estimates.end(), now.begin(), now.end());
  }
  const std::vector<Gaussian3> rest = run.finish();
  estimates.insert(estimates.end(), rest.begin(), rest.end());
  report = run.report();
  return estimates;
}

TEST(NamedMethodRun, PartsOfAnySizeGiveTheWholeRunsEstimates) {
  ASSERT_GT(parts_of(many_scenes(), kScenesPerFilterBlock).size(), 2u);
  for (const std::string method : {"ours", "ours-l", "sttp", "wls", "mmt"}) {
    MethodRunReport whole_report;
    const std::vector<Gaussian3> whole =
        run_named_method(method, MethodConfig{}, &model(), "model.pt", many_scenes(), &whole_report);
    for (const std::size_t scenes : {kScenesPerFilterBlock, std::size_t{7}, std::size_t{256}}) {
      MethodRunReport parts_report;
      expect_identical(in_parts(method, scenes, parts_report), whole, method + " in parts of " + std::to_string(scenes));
      EXPECT_EQ(parts_report.restarted_tracks, whole_report.restarted_tracks) << method;
      EXPECT_EQ(parts_report.registration_missing, whole_report.registration_missing) << method;
      EXPECT_EQ(parts_report.gating.checked, whole_report.gating.checked) << method;
    }
  }
}

// With the registration prior's scales, or Q's, learned across scenes, each scene's start comes from
// the epochs before its own, whatever the parts: the same estimates, bit for bit, and different from
// each scene learning its own. The synthetic views have no offsets, so the default (the run's scales
// lowering a scene's start) lowers them too.
TEST(NamedMethodRun, ScalesAcrossScenesDoNotDependOnTheParts) {
  const std::string prior = "ours:\n  registration_translation_sigma_m: 0.1\n  registration_noise_ratio: 0.5\n";
  const MethodConfig per_scene =
      parse_method_config("c.yaml", prior + "  registration_prior_scale: per-scene\n  process_noise_scale: per-scene\n");
  MethodRunReport own_report;
  const std::vector<Gaussian3> own = run_named_method("ours", per_scene, &model(), "model.pt", many_scenes(), &own_report);
  const auto median_translation = [](const MethodRunReport& report) {
    std::vector<double> translation;
    for (const RegistrationPriorScales& scales : report.registration_prior_scales.fixed.scales) {
      translation.push_back(scales.translation);
    }
    std::nth_element(translation.begin(), translation.begin() + translation.size() / 2, translation.end());
    return translation[translation.size() / 2];
  };
  for (const std::string pooled : {"registration_prior_scale: across-scenes", "registration_prior_scale: shrink-across-scenes",
                                   "registration_prior_scale: per-scene\n  process_noise_scale: across-scenes",
                                   "registration_prior_scale: per-scene\n  process_noise_scale: grow-across-scenes"}) {
    const MethodConfig across = parse_method_config("c.yaml", prior + "  " + pooled + "\n");
    MethodRunReport whole_report;
    const std::vector<Gaussian3> whole = run_named_method("ours", across, &model(), "model.pt", many_scenes(), &whole_report);
    for (const std::size_t scenes : {kScenesPerFilterBlock, std::size_t{7}, std::size_t{256}}) {
      MethodRunReport parts_report;
      expect_identical(in_parts("ours", scenes, parts_report, across), whole, pooled + " in parts of " + std::to_string(scenes));
    }
    // With the registration's scales pooled, the scenes after the first 16 ran with them, every one
    // reported; the pool lowered them below what each scene alone learns.
    if (pooled.find("process_noise_scale") == std::string::npos) {
      EXPECT_GE(whole_report.registration_prior_scales.fixed.scales.size(), 300u - 16u) << pooled;
      EXPECT_TRUE(whole_report.registration_prior_scales.moving.scales.empty()) << "the synthetic views stand still";
      EXPECT_LT(median_translation(whole_report), 0.5 * median_translation(own_report)) << pooled;
    }
    std::size_t differing = 0;
    for (std::size_t k = 0; k < own.size(); ++k) differing += own[k].covariance() != whole[k].covariance();
    EXPECT_GT(differing, 0u) << pooled;
  }
}

// Q's scales are learned across scenes, by default below 1 too for a model trained on several
// benchmarks (one Q for several kinds of motion), and held at 1 and above for a model of one (its Q
// calibrated on its kind of data); as set otherwise.
TEST(NamedMethodRun, LearnsQAcrossScenesBelowItsCalibrationOnlyForAModelOfSeveralBenchmarks) {
  using enum ProcessNoiseScaleLearning;
  const nlohmann::json several = {{"benchmark", {"mpl", "cad"}}};
  const nlohmann::json one = {{"benchmark", "mpl"}};
  const OursSettings automatic;
  EXPECT_EQ(process_noise_scale_learning_for(automatic, several), kAcrossScenes);
  EXPECT_EQ(process_noise_scale_learning_for(automatic, one), kGrowAcrossScenes);
  EXPECT_EQ(process_noise_scale_learning_for(automatic, nlohmann::json::object()), kGrowAcrossScenes);
  EXPECT_EQ(process_noise_scale_learning_for(automatic, {{"benchmark", {"mpl"}}}), kGrowAcrossScenes);
  for (const ProcessNoiseScaleLearning learning : {kPerScene, kAcrossScenes, kGrowAcrossScenes}) {
    OursSettings set;
    set.process_noise_scale_learning = learning;
    EXPECT_EQ(process_noise_scale_learning_for(set, several), learning);
    EXPECT_EQ(process_noise_scale_learning_for(set, one), learning);
  }
}

// The registration prior's scales by default: where the sensors move, learned across scenes from the
// earlier scenes' evidence for every model; where they stand still, only lowered by the run's scenes
// for a model trained on several benchmarks (a compromise prior), per scene for a model of one; as set
// otherwise, whatever the sensors.
TEST(NamedMethodRun, LearnsRegistrationScalesAcrossScenesByTheSensorsMotion) {
  using enum RegistrationScaleLearning;
  const nlohmann::json several = {{"benchmark", {"mpl", "cad"}}};
  const nlohmann::json one = {{"benchmark", "mpl"}};
  const OursSettings automatic;
  EXPECT_EQ(registration_scale_learning_for(automatic, several, SensorMotion::kFixed), kShrinkAcrossScenes);
  EXPECT_EQ(registration_scale_learning_for(automatic, one, SensorMotion::kFixed), kPerScene);
  EXPECT_EQ(registration_scale_learning_for(automatic, nlohmann::json::object(), SensorMotion::kFixed), kPerScene);
  for (const nlohmann::json& metadata : {several, one, nlohmann::json::object()}) {
    EXPECT_EQ(registration_scale_learning_for(automatic, metadata, SensorMotion::kMoving), kAcrossScenes);
    for (SensorMotion sensors : kSensorMotions) {
      for (const RegistrationScaleLearning set : {kPerScene, kAcrossScenes, kShrinkAcrossScenes}) {
        OursSettings settings;
        settings.registration_scale_learning = set;
        EXPECT_EQ(registration_scale_learning_for(settings, metadata, sensors), set);
      }
    }
  }
}

// many_scenes() with every view of every scene off by an offset the rows do not state, σ = 0.5 m per
// horizontal axis (five times the prior's below); its sensors carried along x at 2 m/s where `moving`
// (1.4 m over a scene's 8 steps, beyond kMovingSensorDistance).
std::vector<Measurement> offset_scenes(bool moving) {
  std::vector<Measurement> rows = many_scenes();
  std::mt19937_64 random(17);
  std::normal_distribution<double> offset(0.0, 0.5);
  std::map<std::pair<std::string, std::string>, Vector3d> offsets;
  std::map<std::string, double> start;
  for (Measurement& row : rows) {
    auto [it, drawn] = offsets.try_emplace({row.scene, row.view}, Vector3d::Zero());
    if (drawn) it->second = Vector3d(offset(random), offset(random), 0.0);
    row.position = Gaussian3::from_covariance(row.position.mean() + it->second, row.position.covariance());
    const double first = start.try_emplace(row.scene, row.time).first->second;
    if (moving && row.sensor_position) *row.sensor_position += Vector3d(2.0 * (row.time - first), 0.0, 0.0);
  }
  return rows;
}

// The scenes of fixed and of moving sensors learn the registration's scales in separate pools, each
// as it is used: offsets five times the prior's raise the moving sensors' scales for every scene after
// the first 16 (held at what the scenes before show), while fixed sensors' scenes, whose pool may only
// lower their translations' start, learn those within a few times of the prior's.
TEST(NamedMethodRun, PoolsTheRegistrationScalesOfMovingSensorsApart) {
  const MethodConfig config =
      parse_method_config("c.yaml", "ours:\n  registration_translation_sigma_m: 0.1\n  registration_noise_ratio: 0.5\n");
  const FilterOptions options = filter_options_for(config.ours, model().metadata(), "model.pt");
  const auto median = [](std::vector<double> values) {
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return values[values.size() / 2];
  };
  PerSensorMotion<double> translation;
  for (const bool moving : {false, true}) {
    RegistrationScalePool lowered(RegistrationScalePool::Use::kTranslationLoweredOnly),
        held(RegistrationScalePool::Use::kEvidence);
    const std::vector<Measurement> rows = offset_scenes(moving);
    const FilterRun run = run_spatiotemporal_graph_filter(model(), options, rows, false,
                                                          ScenePools{.registration = {.fixed = &lowered, .moving = &held}});
    const SensorMotion sensors = moving ? SensorMotion::kMoving : SensorMotion::kFixed;
    const SensorMotion other = moving ? SensorMotion::kFixed : SensorMotion::kMoving;
    EXPECT_TRUE(run.registration_prior_scales[other].scales.empty()) << moving;
    const std::vector<RegistrationPriorScales>& learned = run.registration_prior_scales[sensors].scales;
    ASSERT_GE(learned.size(), 300u - 16u) << moving;
    std::vector<double> kappa;
    for (const RegistrationPriorScales& scales : learned) kappa.push_back(scales.translation);
    translation[sensors] = median(kappa);
  }
  // The offsets' variance is 25 times the prior's.
  EXPECT_GT(translation.moving, 10.0);
  EXPECT_LT(translation.fixed, 0.5 * translation.moving);
}

// many_scenes() with every view of every scene off by an offset in units of its rows' noise, δ_u of
// σ 2.5 per horizontal axis (five times the prior's α below): each row moved by L δ_u, L the lower
// Cholesky factor of its covariance.
std::vector<Measurement> noise_offset_scenes() {
  std::vector<Measurement> rows = many_scenes();
  std::mt19937_64 random(19);
  std::normal_distribution<double> offset(0.0, 2.5);
  std::map<std::pair<std::string, std::string>, Vector3d> offsets;
  for (Measurement& row : rows) {
    auto [it, drawn] = offsets.try_emplace({row.scene, row.view}, Vector3d::Zero());
    if (drawn) it->second = Vector3d(offset(random), offset(random), 0.0);
    const Matrix3d covariance = row.position.covariance();
    const Matrix3d factor = covariance.llt().matrixL();
    row.position = Gaussian3::from_covariance(row.position.mean() + factor * it->second, covariance);
  }
  return rows;
}

// With `shrink-across-scenes` on fixed sensors the run's pool lowers the translations' scale only and
// sets κ_n either way, unless the prior has a range scale (its ridge with δ along the rays: every scale
// then lowered only; registration_scale_pool.hpp). Offsets in units of the noise 25 times the prior's
// variance: taken from the run without a range scale, held near the prior's with one.
TEST(NamedMethodRun, RaisesTheNoiseScaleFromTheRunOnlyWithoutARangeScale) {
  const std::vector<Measurement> rows = noise_offset_scenes();
  const auto median_noise_scale = [&rows](const std::string& range_scale) {
    MethodRunReport report;
    run_named_method("ours",
                     parse_method_config("c.yaml",
                                         "ours:\n  registration_translation_sigma_m: 0.01\n"
                                         "  registration_noise_ratio: 0.5\n"
                                         "  registration_range_scale_sigma: " +
                                             range_scale +
                                             "\n"
                                             "  registration_prior_scale: shrink-across-scenes\n"),
                     &model(), "model.pt", rows, &report);
    std::vector<double> kappa;
    for (const RegistrationPriorScales& scales :
         report.registration_prior_scales[SensorMotion::kFixed].scales) {
      kappa.push_back(scales.noise_ratio);
    }
    EXPECT_GE(kappa.size(), 300u - 16u) << range_scale;
    std::sort(kappa.begin(), kappa.end());
    return kappa.empty() ? 0.0 : kappa[kappa.size() / 2];
  };
  const double without = median_noise_scale("0"), with = median_noise_scale("0.01");
  EXPECT_GT(without, 10.0);        // 21 (25 is right)
  EXPECT_GT(without, 2.0 * with);  // 7.3
}

TEST(NamedMethodRun, SttpAndModelFreeMethodsTakeAnyParts) {
  for (const std::string method : {"sttp", "wls", "aom"}) {
    const std::vector<Gaussian3> whole = run_named_method(method, MethodConfig{}, &model(), "model.pt", many_scenes());
    for (const std::size_t scenes : {1u, 7u, 256u}) {
      MethodRunReport report;
      expect_identical(in_parts(method, scenes, report), whole, method + " in parts of " + std::to_string(scenes));
    }
  }
}

// sttp's estimates of a part wait for the forward pass that holds its last graph.
TEST(SingleViewPredictionStream, EstimatesComeOnceTheirPassHasRun) {
  const std::vector<std::span<const Measurement>> parts = parts_of(many_scenes(), 120);
  ASSERT_EQ(parts.size(), 3u);
  std::vector<std::size_t> graphs;  // sttp's graphs of each part
  for (std::span<const Measurement> part : parts) {
    graphs.push_back(make_motion_graph_set(part, HistorySource::kRawView, 5, model().prediction_horizon()).graphs.size());
  }
  const std::size_t pass = SingleViewPredictionStream::kGraphsPerForwardPass;
  // The first pass ends within the second part, and no later pass is full.
  ASSERT_LT(graphs[0], pass);
  ASSERT_GT(graphs[0] + graphs[1], pass);
  ASSERT_LT(graphs[0] + graphs[1] + graphs[2], 2 * pass);
  SingleViewPredictionStream stream(model());
  EXPECT_EQ(stream.add(parts[0]).size(), 0u);
  EXPECT_EQ(stream.add(parts[1]).size(), parts[0].size());
  EXPECT_EQ(stream.add(parts[2]).size(), 0u);
  EXPECT_EQ(stream.finish().size(), parts[1].size() + parts[2].size());
}

TEST(NamedMethodRun, LearnedMethodsNeedTheModel) {
  EXPECT_THROW(NamedMethodRun("ours", MethodConfig{}, nullptr, ""), std::invalid_argument);
  EXPECT_THROW(NamedMethodRun("sttp", MethodConfig{}, nullptr, ""), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
