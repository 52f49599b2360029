// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/cad_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "stgf/datasets/kitti_tracking.hpp"
#include "stgf/datasets/option_checks.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/recording.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr double kPi = portable::kPi;
constexpr double kRateHz = 10.0;  // KITTI's frame rate: t = frame / 10
constexpr std::string_view kSplitNames[] = {"train", "val", "test"};

// ── Geometry ──

double dot3(const Vector3d& a, const Vector3d& b) { return a.x() * b.x() + a.y() * b.y() + a.z() * b.z(); }

// Where a vehicle's sensor is and where it looks (unit, horizontal).
struct SensorPose {
  Vector3d position;
  double heading_x = 1.0;
  double heading_y = 0.0;
};

SensorPose horizontal_pose(const Vector3d& position, const Vector3d& heading) {
  const double length = std::sqrt(heading.x() * heading.x() + heading.y() * heading.y());
  if (!(length > 1e-9)) throw std::runtime_error("cad benchmark: a vehicle heading is vertical");
  return {position, heading.x() / length, heading.y() / length};
}

SensorPose ego_sensor(const KittiFrame& frame) {
  return horizontal_pose(frame.camera_position, frame.ego_heading);
}

SensorPose vehicle_sensor(const KittiObject& vehicle, double sensor_height_m) {
  Vector3d position = vehicle.world_position;
  position.z() += sensor_height_m;
  return horizontal_pose(position, vehicle.world_heading);
}

// Within range and the horizontal field of view: d·h ≥ ‖d‖ cos(fov/2).
bool is_visible(const SensorPose& sensor, const Vector3d& target, double max_range_m,
                double half_fov_cosine) {
  const Vector3d offset = target - sensor.position;
  if (!(dot3(offset, offset) <= max_range_m * max_range_m)) return false;
  const double along = offset.x() * sensor.heading_x + offset.y() * sensor.heading_y;
  const double horizontal = std::sqrt(offset.x() * offset.x() + offset.y() * offset.y());
  return along >= horizontal * half_fov_cosine;
}

// ── Source data ──

struct Source {
  KittiSequence sequence;
  // frame → track id → the box
  std::vector<std::map<int, const KittiObject*>> boxes;

  const KittiObject* box(int frame, int track_id) const {
    const auto& frame_boxes = boxes[static_cast<std::size_t>(frame)];
    const auto it = frame_boxes.find(track_id);
    return it == frame_boxes.end() ? nullptr : it->second;
  }
};

Source load_source(const std::string& directory, const std::string& name) {
  Source source;
  source.sequence = load_kitti_sequence(directory, name);
  source.boxes.resize(source.sequence.frames.size());
  for (const KittiFrame& frame : source.sequence.frames) {
    for (const KittiObject& object : frame.objects) {
      source.boxes[static_cast<std::size_t>(frame.frame)][object.track_id] = &object;
    }
  }
  return source;
}

bool is_vehicle_type(std::string_view type) { return type == "Car" || type == "Van" || type == "Truck"; }

// ── Windows ──

struct EligibleWindow {
  std::size_t source = 0;  // index into the split's sources
  int first_frame = 0;
  std::vector<int> vehicles;            // other vehicles' track ids, views v1, v2, ... in this order
  std::vector<std::string> object_ids;  // eligible objects (kitti_object_id), sorted
  std::map<std::string, int> track_of;  // object id → track id
};

struct WindowCounts {
  int candidate = 0;
  int too_few_vehicles = 0;
  int too_few_objects = 0;
  int eligible = 0;
};

class WindowFinder {
 public:
  WindowFinder(const CadOptions& options, const RandomStream& root)
      : options_(options),
        vehicle_streams_(root.child("vehicles")),
        half_fov_cosine_(portable::sin_cos(options.field_of_view_deg * kPi / 360.0).cosine),
        visible_frames_needed_(
            static_cast<int>(std::ceil(options.min_visible_fraction * options.steps - 1e-9))) {}

  // Every eligible window of `source` (index `source_index`), counting the rejected ones.
  void find(const Source& source, std::size_t source_index, std::vector<EligibleWindow>& windows,
            WindowCounts& counts) const {
    const int frame_count = static_cast<int>(source.sequence.frames.size());
    const RandomStream sequence_stream = vehicle_streams_.child(source.sequence.name);
    for (int first = 0; first + options_.steps <= frame_count; ++first) {
      ++counts.candidate;
      const std::vector<int> present = present_tracks(source, first);
      std::vector<std::string> moving;
      std::map<std::string, int> track_of;
      for (const int track : present) {
        if (is_moving_vehicle(source, track, first))
          moving.push_back(kitti_object_id(source.sequence.name, track));
        track_of[kitti_object_id(source.sequence.name, track)] = track;
      }
      std::sort(moving.begin(), moving.end());
      if (1 + static_cast<int>(moving.size()) < options_.min_vehicles) {
        ++counts.too_few_vehicles;
        continue;
      }
      RandomStream choice = sequence_stream.child(static_cast<std::uint64_t>(first));
      const int wanted = std::min(options_.max_vehicles - 1, static_cast<int>(moving.size()));
      const std::vector<std::string> drawn = choose_ids(choice, moving, wanted);
      std::vector<int> vehicles;
      for (const std::string& id : drawn) vehicles.push_back(track_of.at(id));

      while (true) {
        std::vector<std::string> eligible = eligible_objects(source, first, present, vehicles);
        if (static_cast<int>(eligible.size()) >= options_.objects) {
          EligibleWindow window;
          window.source = source_index;
          window.first_frame = first;
          window.vehicles = vehicles;
          for (const std::string& id : eligible) window.track_of[id] = track_of.at(id);
          window.object_ids = std::move(eligible);
          windows.push_back(std::move(window));
          ++counts.eligible;
          break;
        }
        if (1 + static_cast<int>(vehicles.size()) <= options_.min_vehicles) {
          ++counts.too_few_objects;
          break;
        }
        vehicles.pop_back();  // give the last drawn vehicle (in id order) back: it may be an object now
      }
    }
  }

  bool is_moving_vehicle(const Source& source, int track, int first) const {
    const KittiObject* start = source.box(first, track);
    const KittiObject* end = source.box(first + options_.steps - 1, track);
    if (!is_vehicle_type(start->type)) return false;
    return mean_speed(*start, *end) >= options_.min_vehicle_speed_m_s;
  }

  double mean_speed(const KittiObject& start, const KittiObject& end) const {
    const double dx = end.world_position.x() - start.world_position.x();
    const double dy = end.world_position.y() - start.world_position.y();
    const double duration = static_cast<double>(options_.steps - 1) / kRateHz;
    return std::sqrt(dx * dx + dy * dy) / duration;
  }

  // The sensors of the ego and `vehicles` at `frame`, in view order.
  std::vector<SensorPose> sensors(const Source& source, int frame, const std::vector<int>& vehicles) const {
    std::vector<SensorPose> poses;
    poses.push_back(ego_sensor(source.sequence.frames[static_cast<std::size_t>(frame)]));
    for (const int track : vehicles)
      poses.push_back(vehicle_sensor(*source.box(frame, track), options_.sensor_height_m));
    return poses;
  }

  bool visible(const SensorPose& sensor, const Vector3d& target) const {
    return is_visible(sensor, target, options_.max_range_m, half_fov_cosine_);
  }

 private:
  // Tracks labelled in every frame of the window (Misc left out), by track id.
  std::vector<int> present_tracks(const Source& source, int first) const {
    std::vector<int> present;
    for (const auto& [track, box] : source.boxes[static_cast<std::size_t>(first)]) {
      if (box->type == "Misc") continue;
      bool throughout = true;
      for (int frame = first + 1; frame < first + options_.steps && throughout; ++frame) {
        throughout = source.box(frame, track) != nullptr;
      }
      if (throughout) present.push_back(track);
    }
    return present;
  }

  std::vector<std::string> eligible_objects(const Source& source, int first, const std::vector<int>& present,
                                            const std::vector<int>& vehicles) const {
    std::vector<std::vector<SensorPose>> sensors_by_frame;
    for (int frame = first; frame < first + options_.steps; ++frame) {
      sensors_by_frame.push_back(sensors(source, frame, vehicles));
    }
    std::vector<std::string> eligible;
    for (const int track : present) {
      if (std::find(vehicles.begin(), vehicles.end(), track) != vehicles.end()) continue;
      int seen = 0;
      for (int step = 0; step < options_.steps; ++step) {
        const Vector3d& target = source.box(first + step, track)->world_position;
        const std::vector<SensorPose>& poses = sensors_by_frame[static_cast<std::size_t>(step)];
        if (std::any_of(poses.begin(), poses.end(),
                        [&](const SensorPose& pose) { return visible(pose, target); })) {
          ++seen;
        }
      }
      if (seen >= visible_frames_needed_) eligible.push_back(kitti_object_id(source.sequence.name, track));
    }
    std::sort(eligible.begin(), eligible.end());
    return eligible;
  }

  const CadOptions& options_;
  RandomStream vehicle_streams_;
  double half_fov_cosine_;
  int visible_frames_needed_;
};

// ── Instances ──

struct GpsError {
  double dx = 0.0;
  double dy = 0.0;
  double heading_rad = 0.0;
  double heading_sine = 0.0;
  double heading_cosine = 1.0;
};

GpsError draw_gps_error(const CadOptions& options, RandomStream random) {
  GpsError error;
  // Three draws, always in this order, so turning one error off does not change the others.
  const double xi_x = random.normal();
  const double xi_y = random.normal();
  const double xi_heading = random.normal();
  if (options.gps_position_error_m > 0.0) {
    error.dx = options.gps_position_error_m * xi_x;
    error.dy = options.gps_position_error_m * xi_y;
  }
  if (options.gps_heading_error_deg > 0.0) {
    error.heading_rad = options.gps_heading_error_deg * kPi / 180.0 * xi_heading;
    const portable::SineCosine turn = portable::sin_cos(error.heading_rad);
    error.heading_sine = turn.sine;
    error.heading_cosine = turn.cosine;
  }
  return error;
}

// Rz(δψ) v, written with + only (see synthetic.cpp's `rotated`).
Vector3d rotated(const GpsError& error, const Vector3d& v) {
  const double minus_sine = -error.heading_sine;
  return {error.heading_cosine * v.x() + minus_sine * v.y(),
          error.heading_sine * v.x() + error.heading_cosine * v.y(), v.z()};
}

struct SplitResult {
  BenchmarkSplit split;
  nlohmann::json description;
  nlohmann::json clocks;  // the split's "clocks" entry (null when the clocks are off)
};

// Where an instance's objects come from: its sequence and each object's KITTI track.
struct InstanceTracks {
  const Source* source = nullptr;
  std::map<std::string, int> track_of_object;
};

SplitResult make_split(const CadOptions& options, const RandomStream& root, std::string_view split_name,
                       const std::vector<std::string>& sequence_names, int instances) {
  SplitResult result;
  std::vector<Source> sources;
  for (const std::string& name : sequence_names)
    sources.push_back(load_source(options.source_directory, name));

  const WindowFinder finder(options, root);
  std::vector<EligibleWindow> windows;
  WindowCounts counts;
  nlohmann::json per_sequence = nlohmann::json::object();
  for (std::size_t index = 0; index < sources.size(); ++index) {
    const WindowCounts before = counts;
    const std::size_t first_new = windows.size();
    finder.find(sources[index], index, windows, counts);
    nlohmann::json by_vehicles = nlohmann::json::object();
    for (std::size_t k = first_new; k < windows.size(); ++k) {
      const std::string key = std::to_string(1 + windows[k].vehicles.size());
      by_vehicles[key] = by_vehicles.value(key, 0) + 1;
    }
    per_sequence[sources[index].sequence.name] = {
        {"frames", sources[index].sequence.frames.size()},
        {"dont_care_rows_skipped", sources[index].sequence.dont_care_rows},
        {"candidate_windows", counts.candidate - before.candidate},
        {"eligible_windows", counts.eligible - before.eligible},
        {"eligible_windows_by_vehicles", by_vehicles}};
  }
  if (instances > 0 && windows.empty()) {
    throw std::runtime_error(
        fmt::format("cad benchmark: the {} split has no eligible window in its sequences "
                    "(candidate windows {}, too few vehicles {}, too few objects {})",
                    split_name, counts.candidate, counts.too_few_vehicles, counts.too_few_objects));
  }

  // Windows in a shuffled order (Fisher–Yates); instance k uses order[k mod W].
  const RandomStream split_stream = root.child(split_name);
  std::vector<std::size_t> order(windows.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  RandomStream shuffle = split_stream.child("order");
  for (std::size_t k = order.size(); k > 1; --k) {
    const auto pick = static_cast<std::size_t>(shuffle.uniform01() * static_cast<double>(k));
    std::swap(order[k - 1], order[std::min(pick, k - 1)]);
  }

  std::map<int, int> vehicles_per_instance;
  std::map<std::string, int> object_types;
  std::set<std::size_t> windows_used;
  int moving_objects = 0;
  nlohmann::json instance_list = nlohmann::json::array();
  std::unordered_map<std::string, InstanceTracks> instance_tracks;  // scene → its tracks, for the clocks
  for (int instance = 0; instance < instances; ++instance) {
    const std::size_t window_index = order[static_cast<std::size_t>(instance) % order.size()];
    const EligibleWindow& window = windows[window_index];
    windows_used.insert(window_index);
    const Source& source = sources[window.source];
    const std::string scene = fmt::format("cad-{}-{:04d}", split_name, instance);
    const RandomStream instance_stream = split_stream.child(static_cast<std::uint64_t>(instance));

    RandomStream object_choice = instance_stream.child("objects");
    const std::vector<std::string> objects = choose_ids(object_choice, window.object_ids, options.objects);
    std::vector<int> object_tracks;
    for (const std::string& id : objects) object_tracks.push_back(window.track_of.at(id));
    if (options.clocks.active()) {
      InstanceTracks& tracks = instance_tracks[scene];
      tracks.source = &source;
      for (std::size_t k = 0; k < objects.size(); ++k) tracks.track_of_object[objects[k]] = object_tracks[k];
    }

    const std::size_t vehicle_count = 1 + window.vehicles.size();
    std::vector<GpsError> gps;
    std::vector<RandomStream> sensing;
    const RandomStream gps_root = instance_stream.child("gps");
    const RandomStream sensing_root = instance_stream.child("sensing");
    for (std::size_t vehicle = 0; vehicle < vehicle_count; ++vehicle) {
      gps.push_back(draw_gps_error(options, gps_root.child(vehicle)));
      sensing.push_back(sensing_root.child(vehicle));
    }

    for (int step = 0; step < options.steps; ++step) {
      const int frame = window.first_frame + step;
      const double time = static_cast<double>(frame) / kRateHz;
      for (std::size_t k = 0; k < objects.size(); ++k) {
        result.split.truth.push_back(
            {scene, time, objects[k], source.box(frame, object_tracks[k])->world_position});
      }
      const std::vector<SensorPose> poses = finder.sensors(source, frame, window.vehicles);
      for (std::size_t vehicle = 0; vehicle < vehicle_count; ++vehicle) {
        const SensorPose& sensor = poses[vehicle];
        const GpsError& error = gps[vehicle];
        RandomStream& random = sensing[vehicle];
        const Vector3d reported_sensor(sensor.position.x() + error.dx, sensor.position.y() + error.dy,
                                       sensor.position.z());
        const std::string view = fmt::format("v{}", vehicle);
        for (std::size_t k = 0; k < objects.size(); ++k) {
          const Vector3d& target = source.box(frame, object_tracks[k])->world_position;
          if (!finder.visible(sensor, target)) continue;
          const CadSensorNoise noise = cad_sensor_noise(options, sensor.position, target);
          if (!random.bernoulli(cad_detection_probability(options, noise.range))) continue;
          const double xi0 = random.normal();
          const double xi1 = random.normal();
          const double xi2 = random.normal();
          const double xi[3] = {xi0, xi1, xi2};

          // U' = Rz(δψ) U; p' = s + δc + Rz(δψ)(p − s); z = p' + U' diag(σ) ξ; R = U' diag(σ²) U'ᵀ.
          LineOfSightNoise turned = noise;
          for (int axis = 0; axis < 3; ++axis) turned.basis.col(axis) = rotated(error, noise.basis.col(axis));
          const Matrix3d& basis = turned.basis;
          const Vector3d displaced = reported_sensor + rotated(error, target - sensor.position);
          Vector3d measured;
          for (int row = 0; row < 3; ++row) {
            measured(row) = displaced(row) + (basis(row, 0) * (noise.standard_deviations(0) * xi[0]) +
                                              basis(row, 1) * (noise.standard_deviations(1) * xi[1]) +
                                              basis(row, 2) * (noise.standard_deviations(2) * xi[2]));
          }
          result.split.measurements.push_back({scene, time, view, objects[k],
                                               Gaussian3::from_covariance(measured, turned.covariance()),
                                               reported_sensor, std::nullopt});
        }
      }
    }

    // What the instance is made of.
    ++vehicles_per_instance[static_cast<int>(vehicle_count)];
    nlohmann::json vehicle_list = nlohmann::json::array();
    for (std::size_t vehicle = 0; vehicle < vehicle_count; ++vehicle) {
      const bool ego = vehicle == 0;
      const int track = ego ? -1 : window.vehicles[vehicle - 1];
      vehicle_list.push_back(
          {{"view", fmt::format("v{}", vehicle)},
           {"track", ego ? std::string("ego") : kitti_object_id(source.sequence.name, track)},
           {"type", ego ? std::string("Car") : source.box(window.first_frame, track)->type},
           {"gps_position_error_m", {gps[vehicle].dx, gps[vehicle].dy}},
           {"gps_heading_error_deg", gps[vehicle].heading_rad * 180.0 / kPi}});
    }
    for (std::size_t k = 0; k < objects.size(); ++k) {
      const KittiObject* start = source.box(window.first_frame, object_tracks[k]);
      const KittiObject* end = source.box(window.first_frame + options.steps - 1, object_tracks[k]);
      ++object_types[start->type];
      if (finder.mean_speed(*start, *end) >= options.min_vehicle_speed_m_s) ++moving_objects;
    }
    instance_list.push_back({{"scene", scene},
                             {"sequence", source.sequence.name},
                             {"first_frame", window.first_frame},
                             {"vehicles", vehicle_list},
                             {"objects", objects}});
  }

  if (options.clocks.active()) {
    // Beyond the window: the object's own KITTI box in the frame before and the frames after, when labelled.
    const TrackBeyondWindow kitti_track = [&](const std::string& scene, const std::string& object,
                                              double time) -> std::optional<Vector3d> {
      const InstanceTracks& tracks = instance_tracks.at(scene);
      const long frame = std::lround(time * kRateHz);
      if (frame < 0 || frame >= static_cast<long>(tracks.source->boxes.size())) return std::nullopt;
      const KittiObject* box = tracks.source->box(static_cast<int>(frame), tracks.track_of_object.at(object));
      if (box == nullptr) return std::nullopt;
      return box->world_position;
    };
    result.clocks = apply_view_clocks(result.split, options.clocks, 1.0 / kRateHz, root, kitti_track);
  }

  nlohmann::json vehicle_histogram = nlohmann::json::object();
  for (const auto& [count, number] : vehicles_per_instance) vehicle_histogram[std::to_string(count)] = number;
  result.description = {
      {"sequences", sequence_names},
      {"per_sequence", per_sequence},
      {"candidate_windows", counts.candidate},
      {"eligible_windows", counts.eligible},
      {"rejected_windows",
       {{"too_few_vehicles", counts.too_few_vehicles}, {"too_few_objects", counts.too_few_objects}}},
      {"instances", instances},
      {"distinct_windows_used", windows_used.size()},
      {"vehicles_per_instance", vehicle_histogram},
      {"object_types", object_types},
      {"moving_objects", moving_objects},
      {"instance_list", instance_list},
  };
  return result;
}

nlohmann::json options_json(const CadOptions& options) {
  return {
      {"seed", options.seed},
      {"source_directory", options.source_directory},
      {"train_sequences", options.train_sequences},
      {"val_sequences", options.val_sequences},
      {"test_sequences", options.test_sequences},
      {"train_instances", options.train_instances},
      {"val_instances", options.val_instances},
      {"test_instances", options.test_instances},
      {"steps", options.steps},
      {"rate_hz", kRateHz},
      {"objects", options.objects},
      {"max_vehicles", options.max_vehicles},
      {"min_vehicles", options.min_vehicles},
      {"min_vehicle_speed_m_s", options.min_vehicle_speed_m_s},
      {"min_visible_fraction", options.min_visible_fraction},
      {"sensor_height_m", options.sensor_height_m},
      {"max_range_m", options.max_range_m},
      {"field_of_view_deg", options.field_of_view_deg},
      {"depth_noise_m", options.depth_noise_m},
      {"depth_noise_per_m2", options.depth_noise_per_m2},
      {"lateral_angle_noise_rad", options.lateral_angle_noise_rad},
      {"vertical_angle_noise_rad", options.vertical_angle_noise_rad},
      {"detection_probability_near", options.detection_probability_near},
      {"detection_probability_far", options.detection_probability_far},
      {"gps_position_error_m", options.gps_position_error_m},
      {"gps_heading_error_deg", options.gps_heading_error_deg},
  };
}

}  // namespace

void validate_cad_options(const CadOptions& options) {
  const OptionChecks check("cad benchmark");
  if (options.source_directory.empty()) check.reject("source_directory must not be empty");
  check.whole("train_instances", options.train_instances, 0);
  check.whole("val_instances", options.val_instances, 0);
  check.whole("test_instances", options.test_instances, 0);
  check.whole("steps", options.steps, 2);
  check.whole("objects", options.objects, 1);
  check.whole("max_vehicles", options.max_vehicles, 1);
  check.whole("min_vehicles", options.min_vehicles, 1);
  check.size((static_cast<double>(options.train_instances) + options.val_instances + options.test_instances) *
                 options.steps * options.objects * options.max_vehicles,
             "instances × steps × objects × vehicles");
  check.range("min_vehicles", options.min_vehicles, "max_vehicles", options.max_vehicles);

  const std::vector<std::string>* lists[] = {&options.train_sequences, &options.val_sequences,
                                             &options.test_sequences};
  const int instances[] = {options.train_instances, options.val_instances, options.test_instances};
  std::map<std::string, std::string_view> owner;
  for (std::size_t split = 0; split < 3; ++split) {
    if (instances[split] > 0 && lists[split]->empty()) {
      check.reject(fmt::format("{}_sequences must not be empty when {}_instances is {}", kSplitNames[split],
                               kSplitNames[split], instances[split]));
    }
    for (const std::string& name : *lists[split]) {
      if (name.empty() || name.find_first_of("/\\") != std::string::npos) {
        check.reject(fmt::format("{}_sequences has a bad sequence name '{}'", kSplitNames[split], name));
      }
      const auto [it, fresh] = owner.emplace(name, kSplitNames[split]);
      if (!fresh) {
        check.reject(fmt::format(
            "sequence {} is in {}_sequences and {}_sequences: splits must be disjoint by sequence", name,
            it->second, kSplitNames[split]));
      }
    }
  }

  check.not_negative("min_vehicle_speed_m_s", options.min_vehicle_speed_m_s);
  check.real("min_visible_fraction", options.min_visible_fraction,
             options.min_visible_fraction >= 0.0 && options.min_visible_fraction <= 1.0, "in [0, 1]");
  check.not_negative("sensor_height_m", options.sensor_height_m);
  check.positive("max_range_m", options.max_range_m);
  check.real("field_of_view_deg", options.field_of_view_deg,
             options.field_of_view_deg > 0.0 && options.field_of_view_deg <= 360.0, "in (0, 360]");
  check.positive("depth_noise_m", options.depth_noise_m);
  check.not_negative("depth_noise_per_m2", options.depth_noise_per_m2);
  check.positive("lateral_angle_noise_rad", options.lateral_angle_noise_rad);
  check.positive("vertical_angle_noise_rad", options.vertical_angle_noise_rad);
  check.probability("detection_probability_near", options.detection_probability_near);
  check.real("detection_probability_far", options.detection_probability_far,
             options.detection_probability_far >= 0.0 && options.detection_probability_far <= 1.0 &&
                 options.detection_probability_far <= options.detection_probability_near,
             "a probability in [0, detection_probability_near]");
  check.not_negative("gps_position_error_m", options.gps_position_error_m);
  check.not_negative("gps_heading_error_deg", options.gps_heading_error_deg);
  check_view_clock_options(check, options.clocks, 1.0 / kRateHz);
}

CadSensorNoise cad_sensor_noise(const CadOptions& options, const Vector3d& sensor, const Vector3d& target) {
  CadSensorNoise noise = line_of_sight(sensor, target);
  const double range = noise.range;
  noise.standard_deviations =
      Vector3d(options.depth_noise_m + options.depth_noise_per_m2 * (range * range),
               range * options.lateral_angle_noise_rad, range * options.vertical_angle_noise_rad);
  return noise;
}

double cad_detection_probability(const CadOptions& options, double range_m) {
  return range_detection_probability(range_m, options.max_range_m, options.detection_probability_near,
                                     options.detection_probability_far);
}

Benchmark make_cad_benchmark(const CadOptions& options) {
  validate_cad_options(options);
  const RandomStream root(options.seed);
  Benchmark benchmark;
  SplitResult train = make_split(options, root, "train", options.train_sequences, options.train_instances);
  SplitResult val = make_split(options, root, "val", options.val_sequences, options.val_instances);
  SplitResult test = make_split(options, root, "test", options.test_sequences, options.test_instances);
  benchmark.train = std::move(train.split);
  benchmark.val = std::move(val.split);
  benchmark.test = std::move(test.split);
  benchmark.description = {
      {"source", "KITTI tracking (Geiger, Lenz, Urtasun, CVPR 2012): label, oxts and calib files"},
      {"source_directory", options.source_directory},
      {"seed", options.seed},
      {"options", options_json(options)},
      {"splits",
       {{"train", std::move(train.description)},
        {"val", std::move(val.description)},
        {"test", std::move(test.description)}}},
      {"frame",
       "world = the IMU frame at frame 0 of each sequence (x forward, y left, z up; m), from the oxts poses "
       "(Mercator with scale cos(lat0), R = Rz(yaw) Ry(pitch) Rx(roll)); truth = labelled box bottom "
       "centres"},
      {"views",
       "v0 = the ego car (sensor at the reference camera, looking along the oxts yaw); v1..v3 = other moving "
       "Car/Van/Truck tracks present throughout the window (sensor at the box bottom centre + "
       "sensor_height_m, "
       "looking along the label heading); each instance's real track ids are in instance_list"},
      {"selection",
       "window = steps consecutive frames; vehicles = ego + min(max_vehicles - 1, #moving) moving vehicles "
       "(mean window speed >= min_vehicle_speed_m_s) drawn per window, reduced while fewer than `objects` "
       "objects are eligible; eligible object = present in every frame, not Misc, not a vehicle, visible "
       "(range "
       "and field of view) to some vehicle in >= ceil(min_visible_fraction * steps) frames; windows with "
       "fewer "
       "than min_vehicles vehicles are rejected; instance k uses shuffled eligible window k mod W"},
      {"noise_model",
       "z = p' + U' diag(sigma) xi, xi ~ N(0, I), R = U' diag(sigma^2) U'^T, U' = Rz(dpsi) U, U = [range, "
       "horizontal across, vertical across] line-of-sight axes from the vehicle's true sensor; sigma_depth = "
       "depth_noise_m + depth_noise_per_m2 r^2, sigma_across = r lateral_angle_noise_rad, sigma_vertical = r "
       "vertical_angle_noise_rad"},
      {"gps_model",
       "per vehicle and instance dc = (N(0, gps_position_error_m^2), N(0, gps_position_error_m^2), 0), dpsi "
       "~ "
       "N(0, gps_heading_error_deg^2); p' = s + dc + Rz(dpsi)(p - s) with s the true sensor position; "
       "sensor_x/y/z = s + dc (reported); not in R"},
      {"miss_model",
       "a visible object (within max_range_m and field_of_view_deg) is detected with probability P_near - "
       "(P_near - P_far) (r / max_range_m)^2, independently per vehicle, object and step; no occlusion"},
  };
  if (options.clocks.active()) {
    benchmark.description["clocks"] = view_clocks_json(
        options.clocks, 1.0 / kRateHz,
        {{"train", std::move(train.clocks)}, {"val", std::move(val.clocks)}, {"test", std::move(test.clocks)}});
  }
  return benchmark;
}

}  // namespace stgf
