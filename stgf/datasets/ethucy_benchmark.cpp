// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/ethucy_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <unordered_map>
#include <stdexcept>
#include <utility>

#include "stgf/datasets/gaussian_noise.hpp"
#include "stgf/datasets/option_checks.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/view_noise_options.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr double kTwoPi = 2.0 * portable::kPi;
constexpr double kSquareRootOfTwo = 1.4142135623730950488;

// The line-of-sight noise and miss model of synthetic.hpp with this benchmark's parameters (only the
// members line_of_sight_noise and detection_probability read are set).
SyntheticOptions line_of_sight_model(const EthUcyOptions& options) {
  SyntheticOptions model;
  model.range_noise_m = options.range_noise_m;
  model.range_noise_per_m2 = options.range_noise_per_m2;
  model.cross_noise_m = options.cross_noise_m;
  model.cross_noise_per_m = options.cross_noise_per_m;
  model.vertical_noise_m = options.vertical_noise_m;
  model.vertical_noise_per_m = options.vertical_noise_per_m;
  model.max_range_m = options.max_range_m;
  model.detection_probability_near = options.detection_probability_near;
  model.detection_probability_far = options.detection_probability_far;
  return model;
}

struct BoundingBox {
  double x_min = std::numeric_limits<double>::infinity();
  double x_max = -std::numeric_limits<double>::infinity();
  double y_min = std::numeric_limits<double>::infinity();
  double y_max = -std::numeric_limits<double>::infinity();
};

BoundingBox bounding_box(const Recording& recording) {
  BoundingBox box;
  for (const auto& [frame, objects] : recording.frames) {
    for (const auto& [id, position] : objects) {
      box.x_min = std::min(box.x_min, position.x());
      box.x_max = std::max(box.x_max, position.x());
      box.y_min = std::min(box.y_min, position.y());
      box.y_max = std::max(box.y_max, position.y());
    }
  }
  return box;
}

// ── Splits and windows ──

// Frames [first_frame, end_frame) of one file that a split uses, and its eligible windows there.
struct SplitPart {
  std::size_t file = 0;  // index into the files
  int first_frame = 0;
  int end_frame = 0;
  std::vector<Window> windows;
};

struct SplitPlan {
  std::string name;  // "train", "val", "test"
  int requested = 0;
  std::vector<SplitPart> parts;

  std::size_t window_count() const {
    std::size_t count = 0;
    for (const SplitPart& part : parts) count += part.windows.size();
    return count;
  }
};

// How many instances each of `windows` windows gives for `instances` instances (0 = one each):
// ⌊N/W⌋ each, plus one for N mod W windows chosen by selection sampling (Knuth's Algorithm S: window j
// of the W − j left is taken with probability needed / (W − j)).
std::vector<int> instances_per_window(RandomStream& random, std::size_t windows, int instances) {
  std::vector<int> uses(windows, 0);
  if (windows == 0) return uses;
  const std::size_t requested = instances == 0 ? windows : static_cast<std::size_t>(instances);
  const std::size_t each = requested / windows;
  std::size_t needed = requested % windows;
  for (std::size_t index = 0; index < windows; ++index) {
    uses[index] = static_cast<int>(each);
    if (needed == 0) continue;
    const auto remaining = static_cast<double>(windows - index);
    if (random.uniform01() * remaining < static_cast<double>(needed)) {
      ++uses[index];
      --needed;
    }
  }
  return uses;
}

// ── Instances ──

struct InstanceContext {
  const EthUcyOptions& options;
  const SyntheticOptions& model;
};

void add_instance(const InstanceContext& context, const Recording& recording,
                  const std::vector<SyntheticView>& views, const Window& window, const std::string& scene,
                  const RandomStream& instance_random, BenchmarkSplit& split) {
  const EthUcyOptions& options = context.options;
  RandomStream object_random = instance_random.child("objects");
  const int kept = std::min(static_cast<int>(window.present.size()), options.max_objects);
  const std::vector<std::string> objects = choose_ids(object_random, window.present, kept);

  // b per camera: (σ_b ξ₁, σ_b ξ₂, 0), one draw per statement.
  RandomStream bias_random = instance_random.child("bias");
  std::vector<Vector3d> biases;
  for (std::size_t view = 0; view < views.size(); ++view) {
    const double bias_x = options.registration_bias_m * bias_random.normal();
    const double bias_y = options.registration_bias_m * bias_random.normal();
    biases.emplace_back(bias_x, bias_y, 0.0);
  }
  std::vector<RandomStream> sensing;
  const RandomStream sensing_root = instance_random.child("sensing");
  for (std::size_t view = 0; view < views.size(); ++view) sensing.push_back(sensing_root.child(view));

  for (int frame = window.first_frame; frame < window.first_frame + options.steps; ++frame) {
    const double time = static_cast<double>(frame) / recording.rate_hz;
    const std::map<std::string, Vector3d>& present = recording.frames.at(frame);
    for (const std::string& object : objects)
      split.truth.push_back({scene, time, object, present.at(object)});
    for (std::size_t view = 0; view < views.size(); ++view) {
      RandomStream& random = sensing[view];
      for (const std::string& object : objects) {
        const Vector3d& truth = present.at(object);
        const LineOfSightNoise noise = line_of_sight_noise(context.model, views[view], truth);
        if (!random.bernoulli(detection_probability(context.model, noise.range))) continue;
        const Matrix3d covariance = noise.covariance();
        const Vector3d error = draw_gaussian_error(random, covariance);
        const Vector3d measured = truth + biases[view] + error;
        split.measurements.push_back({scene, time, views[view].id, object,
                                      Gaussian3::from_covariance(measured, covariance),
                                      views[view].sensor_position, std::nullopt});
      }
    }
  }
}

// ── Description ──

nlohmann::json options_json(const EthUcyOptions& options) {
  nlohmann::json described = {
      {"seed", options.seed},
      {"source_directory", options.source_directory},
      {"test_scene", options.test_scene},
      {"train_instances", options.train_instances},
      {"val_instances", options.val_instances},
      {"test_instances", options.test_instances},
      {"steps", options.steps},
      {"min_objects", options.min_objects},
      {"max_objects", options.max_objects},
      {"val_fraction", options.val_fraction},
      {"views", options.views},
      {"min_view_standoff_m", options.min_view_standoff_m},
      {"max_view_standoff_m", options.max_view_standoff_m},
      {"registration_bias_m", options.registration_bias_m},
  };
  described.update(view_noise_options_json(options));
  return described;
}

nlohmann::json scene_table_json() {
  nlohmann::json scenes = nlohmann::json::object();
  for (const EthUcyScene& scene : eth_ucy_scenes()) scenes[scene.name] = scene.files;
  return scenes;
}

nlohmann::json recording_json(const EthUcyFile& file, const std::string& role, const BoundingBox& box,
                              const std::vector<SyntheticView>& views) {
  const Recording& recording = file.recording;
  std::set<std::string> pedestrians;
  std::size_t rows = 0;
  for (const auto& [frame, objects] : recording.frames) {
    rows += objects.size();
    for (const auto& [id, position] : objects) pedestrians.insert(id);
  }
  return {
      {"name", recording.name},
      {"file", file.file_name},
      {"scene", file.scene.empty() ? nlohmann::json(nullptr) : nlohmann::json(file.scene)},
      {"role", role},
      {"rate_hz", recording.rate_hz},
      {"rows", rows},
      {"pedestrians", pedestrians.size()},
      {"frames", recording.frames.size()},
      {"first_frame", recording.frames.begin()->first},
      {"last_frame", recording.frames.rbegin()->first},
      {"bounding_box_m", {{"x", {box.x_min, box.x_max}}, {"y", {box.y_min, box.y_max}}}},
      {"views", describe_synthetic_views(views)},
  };
}

constexpr const char* kNoiseModel =
    "z = p + b + e, e ~ N(0, R), R = U diag(sigma^2) U^T with U = [along, horizontal across, vertical "
    "across] the camera's line of sight; sigma_range = g (range_noise_m + range_noise_per_m2 r^2), "
    "sigma_across = g (cross_noise_m + cross_noise_per_m r), sigma_vertical = g (vertical_noise_m + "
    "vertical_noise_per_m r), r = range from the camera, g = the camera's noise_scale";
constexpr const char* kBiasModel =
    "registration bias b = (registration_bias_m xi1, registration_bias_m xi2, 0), xi ~ N(0, I), drawn per "
    "instance and camera, shared by all of that camera's measurements in the instance, NOT included in R "
    "(registration_bias_m = 0: unbiased, NEES of raw measurements is chi-square with 3 degrees of freedom)";
constexpr const char* kMissModel =
    "detected with probability P_near - (P_near - P_far) (r / max_range_m)^2 within max_range_m, never "
    "beyond; independent per camera, pedestrian and step; no field-of-view limit";
constexpr const char* kCameraModel =
    "per recording, fixed: camera k on the ellipse c + ((sqrt2 w + s_k) cos a_k, (sqrt2 h + s_k) sin a_k) "
    "around the bounding box (centre c, half sizes w, h) of all positions, a_k = a0 + 2 pi k / views + "
    "U[-view_angle_jitter_rad, view_angle_jitter_rad], a0 ~ U[0, 2 pi), s_k ~ U[min_view_standoff_m, "
    "max_view_standoff_m], height U[min_sensor_height_m, max_sensor_height_m], noise_scale "
    "U[min_noise_scale, max_noise_scale]";
constexpr const char* kSplitRule =
    "leave one scene out (Social-GAN / Trajectron++ convention): test = the test scene's files over their "
    "whole frame range; train and val = every other file (the other scenes and crowds_zara03, "
    "uni_examples), each split in time: val = its last val_fraction of frame indices "
    "(round(val_fraction n)), train = the frames before; windows never cross the boundary";
constexpr const char* kWindowRule =
    "eligible window = steps consecutive annotated frames of one file within the split's frame range with "
    "at least min_objects pedestrians present throughout (one window per start frame); of W windows and "
    "N instances (N = 0: N = W) every window gives floor(N/W) instances and N mod W windows drawn without "
    "replacement one more; an instance keeps min(present, max_objects) pedestrians drawn uniformly; "
    "t = frame / 2.5 Hz with frame = frame_id / 10";

}  // namespace

void validate_ethucy_options(const EthUcyOptions& options) {
  const OptionChecks check("ethucy benchmark");
  bool known_scene = false;
  for (const EthUcyScene& scene : eth_ucy_scenes())
    known_scene = known_scene || scene.name == options.test_scene;
  if (!known_scene) {
    check.reject(fmt::format("test_scene must be one of eth, hotel, univ, zara1, zara2 (got '{}')",
                             options.test_scene));
  }
  check.whole("train_instances", options.train_instances, 0);
  check.whole("val_instances", options.val_instances, 0);
  check.whole("test_instances", options.test_instances, 0);
  check.whole("steps", options.steps, 8);
  check.whole("min_objects", options.min_objects, 1);
  check.whole("max_objects", options.max_objects, 1);
  check.range("min_objects", options.min_objects, "max_objects", options.max_objects);
  check.real("val_fraction", options.val_fraction, options.val_fraction > 0.0 && options.val_fraction < 1.0,
             "in (0, 1)");

  check.whole("views", options.views, 1);
  check.size((static_cast<double>(options.train_instances) + options.val_instances + options.test_instances) *
                 options.steps * options.max_objects * options.views,
             "instances × steps × objects × views");
  check.not_negative("min_view_standoff_m", options.min_view_standoff_m);
  check.not_negative("max_view_standoff_m", options.max_view_standoff_m);
  check.range("min_view_standoff_m", options.min_view_standoff_m, "max_view_standoff_m",
              options.max_view_standoff_m);
  check_view_noise_options(check, options);
  check.not_negative("registration_bias_m", options.registration_bias_m);
  check_view_clock_options(check, options.clocks, 1.0 / kEthUcyRateHz);
}

std::vector<SyntheticView> place_ethucy_views(const EthUcyOptions& options, const Recording& recording) {
  validate_ethucy_options(options);
  if (recording.frames.empty()) throw std::invalid_argument("place_ethucy_views: the recording is empty");
  const BoundingBox box = bounding_box(recording);
  const double centre_x = 0.5 * (box.x_min + box.x_max);
  const double centre_y = 0.5 * (box.y_min + box.y_max);
  const double half_width = 0.5 * (box.x_max - box.x_min);
  const double half_height = 0.5 * (box.y_max - box.y_min);

  RandomStream random = RandomStream(options.seed).child("views").child(recording.name);
  const double first_angle = random.uniform(0.0, kTwoPi);
  std::vector<SyntheticView> views;
  for (int index = 0; index < options.views; ++index) {
    const double jitter = random.uniform(-options.view_angle_jitter_rad, options.view_angle_jitter_rad);
    const double angle = first_angle + kTwoPi * index / options.views + jitter;
    const double standoff = random.uniform(options.min_view_standoff_m, options.max_view_standoff_m);
    const double height = random.uniform(options.min_sensor_height_m, options.max_sensor_height_m);
    const double noise_scale = random.uniform(options.min_noise_scale, options.max_noise_scale);
    const portable::SineCosine direction = portable::sin_cos(angle);
    const double x = centre_x + (kSquareRootOfTwo * half_width + standoff) * direction.cosine;
    const double y = centre_y + (kSquareRootOfTwo * half_height + standoff) * direction.sine;
    views.push_back({fmt::format("cam{}", index), Vector3d(x, y, height), noise_scale});
  }
  return views;
}

Benchmark make_ethucy_benchmark(const EthUcyOptions& options) {
  validate_ethucy_options(options);
  const std::vector<EthUcyFile> files = read_eth_ucy_folder(options.source_directory);
  return make_ethucy_benchmark(options, files);
}

Benchmark make_ethucy_benchmark(const EthUcyOptions& options, std::span<const EthUcyFile> files) {
  validate_ethucy_options(options);
  std::set<std::string> names;
  for (const EthUcyFile& file : files) {
    if (file.recording.frames.empty()) {
      throw std::invalid_argument(fmt::format("ethucy benchmark: {} has no samples", file.file_name));
    }
    if (!names.insert(file.recording.name).second) {
      throw std::invalid_argument(
          fmt::format("ethucy benchmark: recording {} given twice", file.recording.name));
    }
  }

  // Frame ranges and eligible windows of every split.
  SplitPlan train{"train", options.train_instances, {}};
  SplitPlan val{"val", options.val_instances, {}};
  SplitPlan test{"test", options.test_instances, {}};
  const auto add_part = [&](SplitPlan& plan, std::size_t file, int first_frame, int end_frame) {
    const Recording& recording = files[file].recording;
    plan.parts.push_back(
        {file, first_frame, end_frame,
         windows_with_objects(recording, first_frame, end_frame, options.steps, options.min_objects)});
  };
  for (std::size_t file = 0; file < files.size(); ++file) {
    const Recording& recording = files[file].recording;
    const int first = recording.frames.begin()->first;
    const int end = recording.frames.rbegin()->first + 1;
    if (files[file].scene == options.test_scene) {
      add_part(test, file, first, end);
    } else {
      // B = F₁ + 1 − ⌊val_fraction · n + ½⌋
      const int val_frames = static_cast<int>(std::floor(options.val_fraction * (end - first) + 0.5));
      const int boundary = end - val_frames;
      add_part(train, file, first, boundary);
      add_part(val, file, boundary, end);
    }
  }

  const SyntheticOptions model = line_of_sight_model(options);
  const InstanceContext context{options, model};
  std::vector<std::vector<SyntheticView>> views;
  std::vector<nlohmann::json> recordings_json;
  for (const EthUcyFile& file : files) {
    views.push_back(place_ethucy_views(options, file.recording));
    const std::string role = file.scene == options.test_scene ? "test" : "train+val";
    recordings_json.push_back(recording_json(file, role, bounding_box(file.recording), views.back()));
  }

  const RandomStream root(options.seed);
  Benchmark benchmark;
  nlohmann::json splits_json = nlohmann::json::object();
  nlohmann::json clocks_json = nlohmann::json::object();
  std::unordered_map<std::string, const Recording*> recording_of_scene;  // for the clocks' tracks
  for (auto [plan, split] : {std::pair{&train, &benchmark.train}, std::pair{&val, &benchmark.val},
                             std::pair{&test, &benchmark.test}}) {
    const std::size_t window_count = plan->window_count();
    if (window_count == 0 && plan->requested > 0) {
      throw std::runtime_error(fmt::format(
          "ethucy benchmark: the {} split has no eligible window ({} steps with at least {} pedestrians "
          "present throughout); lower steps or min_objects",
          plan->name, options.steps, options.min_objects));
    }
    const RandomStream split_random = root.child(plan->name);
    RandomStream window_random = split_random.child("windows");
    const std::vector<int> uses = instances_per_window(window_random, window_count, plan->requested);

    nlohmann::json parts_json = nlohmann::json::array();
    std::size_t window_index = 0;
    int instance = 0;
    for (const SplitPart& part : plan->parts) {
      const EthUcyFile& file = files[part.file];
      const int first_instance = instance;
      for (const Window& window : part.windows) {
        for (int use = 0; use < uses[window_index]; ++use) {
          const std::string scene = fmt::format("ethucy-{}-{:04d}", plan->name, instance);
          add_instance(context, file.recording, views[part.file], window, scene,
                       split_random.child(static_cast<std::uint64_t>(instance)), *split);
          if (options.clocks.active()) recording_of_scene[scene] = &file.recording;
          ++instance;
        }
        ++window_index;
      }
      parts_json.push_back({
          {"recording", file.recording.name},
          {"first_frame", part.first_frame},
          {"last_frame", part.end_frame - 1},
          {"first_time_s", static_cast<double>(part.first_frame) / file.recording.rate_hz},
          {"last_time_s", static_cast<double>(part.end_frame - 1) / file.recording.rate_hz},
          {"eligible_windows", part.windows.size()},
          {"instances", instance - first_instance},
          {"scenes", instance > first_instance
                         ? nlohmann::json{fmt::format("ethucy-{}-{:04d}", plan->name, first_instance),
                                          fmt::format("ethucy-{}-{:04d}", plan->name, instance - 1)}
                         : nlohmann::json::array()},
      });
    }
    if (options.clocks.active()) {
      const TrackBeyondWindow recording_track = [&](const std::string& scene, const std::string& object,
                                                    double time) {
        return recording_position_at(*recording_of_scene.at(scene), object, time);
      };
      clocks_json[plan->name] =
          apply_view_clocks(*split, options.clocks, 1.0 / kEthUcyRateHz, root, recording_track);
    }
    splits_json[plan->name] = {
        {"requested_instances", plan->requested},
        {"instances", instance},
        {"eligible_windows", window_count},
        {"recordings", parts_json},
    };
  }

  nlohmann::json source_files = nlohmann::json::array();
  for (const EthUcyFile& file : files) source_files.push_back(file.file_name);
  benchmark.description = {
      {"source",
       "ETH/UCY pedestrians (ETH: Pellegrini et al., ICCV 2009; UCY: Lerner et al., CGF 2007), "
       "files of StanfordASL/Trajectron-plus-plus experiments/pedestrians/raw/raw/all_data"},
      {"source_directory", options.source_directory},
      {"source_files", source_files},
      {"seed", options.seed},
      {"test_scene", options.test_scene},
      {"options", options_json(options)},
      {"scene_table", scene_table_json()},
      {"training_only_files", eth_ucy_training_only_files()},
      {"recordings", recordings_json},
      {"splits", splits_json},
      {"split_rule", kSplitRule},
      {"window_rule", kWindowRule},
      {"camera_model", kCameraModel},
      {"noise_model", kNoiseModel},
      {"bias_model", kBiasModel},
      {"miss_model", kMissModel},
  };
  if (options.clocks.active())
    benchmark.description["clocks"] = view_clocks_json(options.clocks, 1.0 / kEthUcyRateHz, std::move(clocks_json));
  return benchmark;
}

}  // namespace stgf
