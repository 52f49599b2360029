// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/mpl_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "stgf/datasets/option_checks.hpp"
#include "stgf/datasets/pets2009.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/text_input.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr double kRadiansPerDegree = portable::kPi / 180.0;

std::vector<int> sorted_views(const MplOptions& options) {
  std::vector<int> views = options.views;
  std::sort(views.begin(), views.end());
  return views;
}

// A source file's name within the source folder, size and 64-bit FNV-1a: identifies the exact
// source data in the description.
nlohmann::json file_json(const std::string& path, const std::string& source_directory) {
  const std::string bytes = read_whole_file(path);
  return {{"file", std::filesystem::path(path).lexically_relative(source_directory).generic_string()},
          {"bytes", bytes.size()},
          {"fnv1a64", fmt::format("{:016x}", fnv1a64(bytes))}};
}

// ── One split ──

struct SplitPlan {
  std::string name;  // "train", "val", "test"
  int instances = 0;
  FrameRange frames;
  std::vector<Window> windows;  // eligible windows inside `frames`
};

struct SplitResult {
  BenchmarkSplit split;
  long long rays_missing_the_ground = 0;
  std::map<std::string, long long> measurements_by_view;
};

// One camera in one instance: its view (with the FILE calibration), the TRUE camera of this instance,
// and the stream of its detections and noise.
struct InstanceCamera {
  const MplView* view = nullptr;
  TsaiCamera true_camera;
  RandomStream sensing;
};

TsaiCamera draw_true_camera(const MplOptions& options, const MplView& view, RandomStream random) {
  const double rotation_sigma = options.calibration_rotation_error_deg * kRadiansPerDegree;
  const double translation_sigma = options.calibration_translation_error_m;
  if (rotation_sigma == 0.0 && translation_sigma == 0.0) return view.camera;
  Vector3d rotation_error;
  Vector3d centre_shift;
  for (int axis = 0; axis < 3; ++axis) rotation_error(axis) = rotation_sigma * random.normal();
  for (int axis = 0; axis < 3; ++axis) centre_shift(axis) = translation_sigma * random.normal();
  return view.camera.with_pose_error(rotation_error, centre_shift);
}

// R = [J diag(σ_u², σ_v²) Jᵀ, 0; 0, σ_z²], written out so that it is exactly symmetric.
Matrix3d measurement_covariance(const Matrix2d& jacobian, double variance_u, double variance_v,
                                double variance_z) {
  Matrix3d covariance = Matrix3d::Zero();
  for (int row = 0; row < 2; ++row) {
    for (int column = row; column < 2; ++column) {
      const double entry = variance_u * (jacobian(row, 0) * jacobian(column, 0)) +
                           variance_v * (jacobian(row, 1) * jacobian(column, 1));
      covariance(row, column) = entry;
      covariance(column, row) = entry;
    }
  }
  covariance(2, 2) = variance_z;
  return covariance;
}

class InstanceSimulator {
 public:
  InstanceSimulator(const MplOptions& options, const MplSource& source)
      : options_(options), source_(source) {}

  void simulate(const SplitPlan& plan, int index, const RandomStream& split_random, int index_width,
                SplitResult& result) const {
    const RandomStream instance = split_random.child(static_cast<std::uint64_t>(index));
    RandomStream window_random = instance.child("window");
    const auto window_index = std::min(
        plan.windows.size() - 1,
        static_cast<std::size_t>(window_random.uniform01() * static_cast<double>(plan.windows.size())));
    const Window& window = plan.windows[window_index];
    RandomStream people_random = instance.child("pedestrians");
    const std::vector<std::string> people = choose_ids(people_random, window.present, options_.pedestrians);
    const std::string scene = fmt::format("mpl-{}-{:0{}d}", plan.name, index, index_width);

    std::vector<InstanceCamera> cameras;
    cameras.reserve(source_.views.size());
    const RandomStream calibration_random = instance.child("calibration");
    const RandomStream sensing_random = instance.child("sensing");
    for (const MplView& view : source_.views) {
      const auto number = static_cast<std::uint64_t>(view.number);
      cameras.push_back({&view, draw_true_camera(options_, view, calibration_random.child(number)),
                         sensing_random.child(number)});
    }

    for (int step = 0; step < options_.steps; ++step) {
      const int frame = window.first_frame + step;
      const double time = frame / source_.recording.rate_hz;
      const std::map<std::string, Vector3d>& positions = source_.recording.frames.at(frame);
      for (const std::string& person : people)
        result.split.truth.push_back({scene, time, person, positions.at(person)});
      for (InstanceCamera& camera : cameras) {
        for (const std::string& person : people)
          measure(scene, time, person, positions.at(person), camera, result);
      }
    }
  }

 private:
  // One view's measurement of one person at one step (see the header comment), if any.
  void measure(const std::string& scene, double time, const std::string& person, const Vector3d& truth,
               InstanceCamera& camera, SplitResult& result) const {
    const CameraProjection projection = camera.true_camera.project(truth);
    if (!projection.valid() || !camera.true_camera.is_inside_image(projection.pixel)) return;
    if (!camera.sensing.bernoulli(options_.detection_probability)) return;
    const double noise_u = camera.sensing.normal();
    const double noise_v = camera.sensing.normal();
    const double noise_z = camera.sensing.normal();
    const Vector2d pixel(projection.pixel.x() + options_.pixel_noise_u_px * noise_u,
                         projection.pixel.y() + options_.pixel_noise_v_px * noise_v);
    const TsaiCamera& file_camera = camera.view->camera;
    const std::optional<Vector3d> ground = file_camera.back_project_to_ground(pixel, 0.0);
    if (!ground) {
      ++result.rays_missing_the_ground;
      return;
    }
    const Vector3d measured(ground->x(), ground->y(), options_.ground_height_noise_m * noise_z);
    const Matrix3d covariance = measurement_covariance(
        file_camera.ground_jacobian(pixel, 0.0), options_.pixel_noise_u_px * options_.pixel_noise_u_px,
        options_.pixel_noise_v_px * options_.pixel_noise_v_px,
        options_.ground_height_noise_m * options_.ground_height_noise_m);
    result.split.measurements.push_back({scene, time, camera.view->id, person,
                                         Gaussian3::from_covariance(measured, covariance),
                                         file_camera.centre(), std::nullopt});
    ++result.measurements_by_view[camera.view->id];
  }

  const MplOptions& options_;
  const MplSource& source_;
};

SplitResult make_split(const MplOptions& options, const MplSource& source, const SplitPlan& plan,
                       const RandomStream& root) {
  SplitResult result;
  for (const MplView& view : source.views) result.measurements_by_view[view.id] = 0;
  if (plan.instances == 0) return result;
  if (plan.windows.empty()) {
    throw std::invalid_argument(fmt::format(
        "mpl benchmark: the {} split (frames {}-{}) has no window of {} frames with {} pedestrians present "
        "throughout; ask for fewer steps or pedestrians, or change the instance counts that share out the "
        "frames",
        plan.name, plan.frames.first_frame, plan.frames.end_frame - 1, options.steps, options.pedestrians));
  }
  const InstanceSimulator simulator(options, source);
  const RandomStream split_random = root.child(plan.name);
  const int index_width = std::max(4, static_cast<int>(fmt::format("{}", plan.instances - 1).size()));
  for (int index = 0; index < plan.instances; ++index)
    simulator.simulate(plan, index, split_random, index_width, result);
  return result;
}

// ── Description ──

nlohmann::json options_json(const MplOptions& options) {
  return {
      {"seed", options.seed},
      {"source_directory", options.source_directory},
      {"train_instances", options.train_instances},
      {"val_instances", options.val_instances},
      {"test_instances", options.test_instances},
      {"steps", options.steps},
      {"pedestrians", options.pedestrians},
      {"views", sorted_views(options)},
      {"pixel_noise_u_px", options.pixel_noise_u_px},
      {"pixel_noise_v_px", options.pixel_noise_v_px},
      {"ground_height_noise_m", options.ground_height_noise_m},
      {"detection_probability", options.detection_probability},
      {"calibration_rotation_error_deg", options.calibration_rotation_error_deg},
      {"calibration_translation_error_m", options.calibration_translation_error_m},
  };
}

nlohmann::json describe(const MplOptions& options, const MplSource& source,
                        const std::vector<SplitPlan>& plans, const std::vector<SplitResult>& results) {
  nlohmann::json views = nlohmann::json::array();
  for (const MplView& view : source.views) {
    const Vector3d& centre = view.camera.centre();
    views.push_back({{"id", view.id},
                     {"calibration", view.camera.name()},
                     {"camera_centre_m", {centre.x(), centre.y(), centre.z()}},
                     {"image_size_px", {view.camera.width_px(), view.camera.height_px()}},
                     {"focal_mm", view.camera.intrinsic().focal_mm}});
  }

  std::set<std::string> people;
  long long boxes = 0;
  for (const auto& [frame, positions] : source.recording.frames) {
    for (const auto& [person, position] : positions) people.insert(person);
    boxes += static_cast<long long>(positions.size());
  }

  nlohmann::json splits = nlohmann::json::object();
  for (std::size_t index = 0; index < plans.size(); ++index) {
    const SplitPlan& plan = plans[index];
    splits[plan.name] = {{"first_frame", plan.frames.first_frame},
                         {"end_frame", plan.frames.end_frame},
                         {"eligible_windows", plan.windows.size()},
                         {"instances", plan.instances},
                         {"measurements_by_view", results[index].measurements_by_view},
                         {"rays_missing_the_ground", results[index].rays_missing_the_ground}};
  }

  return {
      {"source", "PETS 2009 S2.L1 (mpl)"},
      {"source_files", source.files},
      {"attribution",
       "PETS 2009 (J. Ferryman, A. Shahrokni, PETS2009: Dataset and challenge, IEEE PETS 2009; video "
       "copyright University of Reading); ground truth by Anton Milan; copied from crowdbotp/OpenTraj"},
      {"recording",
       {{"name", source.recording.name},
        {"rate_hz", source.recording.rate_hz},
        {"first_frame", source.recording.frames.begin()->first},
        {"last_frame", source.recording.frames.rbegin()->first},
        {"people", people.size()},
        {"boxes", boxes}}},
      {"seed", options.seed},
      {"options", options_json(options)},
      {"views", views},
      {"splits", splits},
      {"truth_model",
       "view-1 foot pixels (xc, yc + h/2) back-projected through the View_001 Tsai calibration onto z = 0; "
       "t = frame / 7 s"},
      {"instance_model",
       "splits are contiguous frame ranges (train, val, test) in proportion to the instance counts; an "
       "instance is a window of `steps` frames inside one range, drawn uniformly among the windows with at "
       "least `pedestrians` people present throughout, and `pedestrians` of those people drawn uniformly"},
      {"visibility_model",
       "a view measures a person when its true camera has the foot point in front, inside the distortion "
       "model's domain and inside the image (0 <= u < width, 0 <= v < height), and a detection draw with "
       "detection_probability succeeds"},
      {"noise_model",
       "pixel = true projection + N(0, diag(pixel_noise_u_px^2, pixel_noise_v_px^2)); (x, y) = "
       "back-projection "
       "of the pixel through the file calibration onto z = 0; z = N(0, ground_height_noise_m^2); R = "
       "[J diag(sigma_u^2, sigma_v^2) J^T, 0; 0, sigma_z^2] with J = d(x, y)/d(u, v) of the file calibration "
       "at the measured pixel; sensor = file camera centre"},
      {"calibration_error_model",
       "per instance and camera, the true camera is the file camera turned by N(0, "
       "calibration_rotation_error_deg^2) about each of its own axes and with its centre moved by N(0, "
       "calibration_translation_error_m^2) along each world axis; this bias is not in R"},
  };
}

}  // namespace

void validate_mpl_options(const MplOptions& options) {
  const OptionChecks check("mpl benchmark");
  check.whole("train_instances", options.train_instances, 0);
  check.whole("val_instances", options.val_instances, 0);
  check.whole("test_instances", options.test_instances, 0);
  if (static_cast<long long>(options.train_instances) + options.val_instances + options.test_instances < 1) {
    check.reject("at least one of train, val and test needs instances");
  }
  check.whole("steps", options.steps, 1);
  check.whole("pedestrians", options.pedestrians, 1);
  check.size((static_cast<double>(options.train_instances) + options.val_instances + options.test_instances) *
                 options.steps * options.pedestrians * static_cast<double>(options.views.size()),
             "instances × steps × pedestrians × views");
  if (options.views.empty()) check.reject("views must name at least one camera");
  std::set<int> seen;
  for (const int view : options.views) {
    if (view < 1 || view > 8) {
      check.reject(fmt::format("view {} does not exist (PETS 2009 has views 1 to 8)", view));
    }
    if (!seen.insert(view).second) check.reject(fmt::format("view {} is listed twice", view));
  }
  check.positive("pixel_noise_u_px", options.pixel_noise_u_px);
  check.positive("pixel_noise_v_px", options.pixel_noise_v_px);
  check.positive("ground_height_noise_m", options.ground_height_noise_m);
  check.probability("detection_probability", options.detection_probability);
  check.not_negative("calibration_rotation_error_deg", options.calibration_rotation_error_deg);
  check.not_negative("calibration_translation_error_m", options.calibration_translation_error_m);
  check_view_clock_options(check, options.clocks, 1.0 / kPets2009FrameRateHz);
}

MplSource read_mpl_source(const MplOptions& options) {
  validate_mpl_options(options);
  if (options.source_directory.empty())
    throw std::invalid_argument("mpl benchmark: the source directory is empty");
  MplSource source;
  source.annotation_path = pets2009_annotation_path(options.source_directory);
  source.recording = read_pets2009_recording(options.source_directory);
  source.files = nlohmann::json::array();
  source.files.push_back(file_json(source.annotation_path, options.source_directory));
  // View_001 defines the world trajectories, also when view 1 is not one of the benchmark's views.
  std::set<int> calibrations = {1};
  for (const int number : sorted_views(options)) {
    const std::string path = pets2009_calibration_path(options.source_directory, number);
    source.views.push_back({number, fmt::format("view{}", number), path, read_tsai_camera(path)});
    calibrations.insert(number);
  }
  for (const int number : calibrations) {
    source.files.push_back(
        file_json(pets2009_calibration_path(options.source_directory, number), options.source_directory));
  }
  return source;
}

MplSplitRanges mpl_split_ranges(const MplOptions& options, const Recording& recording) {
  if (recording.frames.empty()) throw std::invalid_argument("mpl benchmark: the recording has no frames");
  const long long first = recording.frames.begin()->first;
  const long long frames = recording.frames.rbegin()->first + 1 - first;
  const long long total =
      static_cast<long long>(options.train_instances) + options.val_instances + options.test_instances;
  if (total < 1)
    throw std::invalid_argument("mpl benchmark: at least one of train, val and test needs instances");
  // first + round(frames · share), with round-half-up in integers.
  const auto boundary = [&](long long instances_before) {
    return static_cast<int>(first + (2 * frames * instances_before + total) / (2 * total));
  };
  const int train_end = boundary(options.train_instances);
  const int val_end = boundary(static_cast<long long>(options.train_instances) + options.val_instances);
  const int end = static_cast<int>(first + frames);
  return {{static_cast<int>(first), train_end}, {train_end, val_end}, {val_end, end}};
}

Benchmark make_mpl_benchmark(const MplOptions& options, const MplSource& source) {
  validate_mpl_options(options);
  const std::vector<int> views = sorted_views(options);
  if (views.size() != source.views.size() ||
      !std::equal(views.begin(), views.end(), source.views.begin(),
                  [](int number, const MplView& view) { return number == view.number; })) {
    throw std::invalid_argument("mpl benchmark: the options' views differ from the views of the source data");
  }
  const MplSplitRanges ranges = mpl_split_ranges(options, source.recording);
  std::vector<SplitPlan> plans = {{"train", options.train_instances, ranges.train, {}},
                                  {"val", options.val_instances, ranges.val, {}},
                                  {"test", options.test_instances, ranges.test, {}}};
  for (SplitPlan& plan : plans) {
    plan.windows = windows_with_objects(source.recording, plan.frames.first_frame, plan.frames.end_frame,
                                        options.steps, options.pedestrians);
  }
  const RandomStream root(options.seed);
  std::vector<SplitResult> results;
  for (const SplitPlan& plan : plans) results.push_back(make_split(options, source, plan, root));

  Benchmark benchmark;
  benchmark.description = describe(options, source, plans, results);
  if (options.clocks.active()) {
    const double period = 1.0 / source.recording.rate_hz;
    const TrackBeyondWindow recording_track = [&](const std::string&, const std::string& person, double time) {
      return recording_position_at(source.recording, person, time);
    };
    nlohmann::json clocks = nlohmann::json::object();
    for (std::size_t k = 0; k < plans.size(); ++k)
      clocks[plans[k].name] = apply_view_clocks(results[k].split, options.clocks, period, root, recording_track);
    benchmark.description["clocks"] = view_clocks_json(options.clocks, period, std::move(clocks));
  }
  benchmark.train = std::move(results[0].split);
  benchmark.val = std::move(results[1].split);
  benchmark.test = std::move(results[2].split);
  return benchmark;
}

Benchmark make_mpl_benchmark(const MplOptions& options) {
  return make_mpl_benchmark(options, read_mpl_source(options));
}

}  // namespace stgf
