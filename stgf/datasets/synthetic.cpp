// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/synthetic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

#include "stgf/datasets/option_checks.hpp"
#include "stgf/datasets/random.hpp"
#include "stgf/datasets/view_noise_options.hpp"

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

constexpr double kTwoPi = 2.0 * portable::kPi;

// ── Small deterministic vector arithmetic (sums in a fixed order) ──

struct Planar {
  double x = 0.0;
  double y = 0.0;
};
Planar operator+(Planar a, Planar b) { return {a.x + b.x, a.y + b.y}; }
Planar operator-(Planar a, Planar b) { return {a.x - b.x, a.y - b.y}; }
Planar operator*(double k, Planar a) { return {k * a.x, k * a.y}; }
double dot(Planar a, Planar b) { return a.x * b.x + a.y * b.y; }
double cross(Planar a, Planar b) { return a.x * b.y - a.y * b.x; }
double length(Planar a) { return std::sqrt(dot(a, a)); }

// (cos θ x − sin θ y, sin θ x + cos θ y), written with + only: GCC 12 fuses the mixed −/+ pair into
// one fused multiply-add-subtract when FMA is available even with contraction off.
Planar rotated(Planar vector, double radians) {
  const portable::SineCosine turn = portable::sin_cos(radians);
  const double minus_sine = -turn.sine;
  return {turn.cosine * vector.x + minus_sine * vector.y, turn.sine * vector.x + turn.cosine * vector.y};
}

// A uniformly random unit vector: a point uniform in the unit disc, normalised.
Planar random_direction(RandomStream& random) {
  while (true) {
    Planar point;
    point.x = random.uniform(-1.0, 1.0);
    point.y = random.uniform(-1.0, 1.0);
    const double squared = dot(point, point);
    if (squared > 1e-12 && squared < 1.0) return (1.0 / std::sqrt(squared)) * point;
  }
}

double sign_of(double value) { return value >= 0.0 ? 1.0 : -1.0; }

// steer(h, d): how hard and which way to turn h toward direction d (see the header comment).
double steer_toward(Planar heading, Planar direction) {
  const double side = cross(heading, direction);
  return dot(heading, direction) >= 0.0 ? side : sign_of(side);
}

// ── Motion ──

struct Walker {
  Planar position;
  Planar velocity;
  Planar heading;  // intended direction of travel, unit length
  double turn_rate = 0.0;
  double preferred_speed = 0.0;
  double stop_remaining_s = 0.0;  // > 0 while stopped
};

class SceneMotion {
 public:
  SceneMotion(const SyntheticOptions& options, RandomStream random)
      : options_(options), random_(std::move(random)) {
    const double period = 1.0 / options.rate_hz;
    substeps_ = std::max(1, static_cast<int>(std::ceil(period / options.max_substep_s - 1e-9)));
    substep_ = period / substeps_;
    turn_rate_memory_ = portable::exp(-substep_ / options.turn_rate_correlation_s);
    turn_rate_innovation_ =
        options.turn_rate_std_rad_s * std::sqrt(1.0 - turn_rate_memory_ * turn_rate_memory_);
    stop_probability_ = 1.0 - portable::exp(-options.stop_rate_per_s * substep_);
    place_walkers();
  }

  // Positions of every object at every step: [step][object].
  std::vector<std::vector<Planar>> run() {
    std::vector<std::vector<Planar>> positions;
    positions.reserve(static_cast<std::size_t>(options_.steps));
    for (int step = 0; step < options_.steps; ++step) {
      if (step > 0) {
        for (int substep = 0; substep < substeps_; ++substep) advance();
      }
      std::vector<Planar> frame;
      frame.reserve(walkers_.size());
      for (const Walker& walker : walkers_) frame.push_back(walker.position);
      positions.push_back(std::move(frame));
    }
    return positions;
  }

 private:
  void place_walkers() {
    const double inner = options_.area_half_width_m - options_.boundary_margin_m;
    constexpr int kPlacementAttempts = 200;
    for (int index = 0; index < options_.objects; ++index) {
      Walker walker;
      for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
        walker.position.x = random_.uniform(-inner, inner);
        walker.position.y = random_.uniform(-inner, inner);
        if (clear_of_others(walker.position)) break;
      }
      walker.heading = random_direction(random_);
      walker.preferred_speed = random_.uniform(options_.min_speed_m_s, options_.max_speed_m_s);
      walker.velocity = walker.preferred_speed * walker.heading;
      walker.turn_rate = random_.normal(0.0, options_.turn_rate_std_rad_s);
      walkers_.push_back(walker);
    }
  }

  bool clear_of_others(Planar position) const {
    return std::all_of(walkers_.begin(), walkers_.end(), [&](const Walker& other) {
      return length(other.position - position) >= options_.avoidance_radius_m;
    });
  }

  // One substep for every object: headings and velocities from the positions at the start of the
  // substep, then all positions.
  void advance() {
    const double dt = substep_;
    for (std::size_t index = 0; index < walkers_.size(); ++index) {
      Walker& walker = walkers_[index];
      update_stop(walker, dt);
      walker.turn_rate = turn_rate_memory_ * walker.turn_rate + turn_rate_innovation_ * random_.normal();

      Avoidance avoidance;
      for (std::size_t other_index = 0; other_index < walkers_.size(); ++other_index) {
        if (other_index == index) continue;
        add_avoidance(walker, walkers_[other_index], index < other_index, avoidance);
      }
      const double turn = walker.turn_rate + boundary_turn(walker) + avoidance.turn_rate;
      walker.heading = rotated(walker.heading, turn * dt);
      walker.heading = (1.0 / length(walker.heading)) * walker.heading;  // keep it unit despite rounding

      const double walking_speed =
          walker.stop_remaining_s > 0.0 ? 0.0 : walker.preferred_speed * (1.0 - avoidance.braking);
      const Planar desired = walking_speed * walker.heading + avoidance.sidestep;
      const Planar change = desired - walker.velocity;
      const double change_length = length(change);
      const double largest_change = options_.max_acceleration_m_s2 * dt;
      walker.velocity = change_length <= largest_change
                            ? desired
                            : walker.velocity + (largest_change / change_length) * change;
    }
    for (Walker& walker : walkers_) walker.position = walker.position + dt * walker.velocity;
  }

  void update_stop(Walker& walker, double dt) {
    if (walker.stop_remaining_s > 0.0) {
      walker.stop_remaining_s = std::max(0.0, walker.stop_remaining_s - dt);
    } else if (random_.bernoulli(stop_probability_)) {
      walker.stop_remaining_s = random_.uniform(options_.min_stop_s, options_.max_stop_s);
    }
  }

  // ω_b: turn toward the centre inside the margin band along the edge.
  double boundary_turn(const Walker& walker) const {
    const double inner = options_.area_half_width_m - options_.boundary_margin_m;
    const double outside = std::max(std::abs(walker.position.x), std::abs(walker.position.y)) - inner;
    if (outside <= 0.0) return 0.0;
    const double depth = std::min(1.0, outside / options_.boundary_margin_m);
    const double distance_to_centre = length(walker.position);
    const Planar toward_centre = (-1.0 / distance_to_centre) * walker.position;
    return options_.boundary_turn_rate_rad_s * depth * steer_toward(walker.heading, toward_centre);
  }

  // What the neighbours within the avoidance radius ask of one object (see the header comment).
  struct Avoidance {
    double turn_rate = 0.0;  // ω_a
    double braking = 0.0;    // β ∈ [0, 1]
    Planar sidestep;         // u_a
  };

  // Adds one neighbour's share of ω_a, β and u_a. Two objects at exactly the same place step apart
  // along x, the lower index toward −x.
  void add_avoidance(const Walker& walker, const Walker& other, bool lower_index,
                     Avoidance& avoidance) const {
    const double radius = options_.avoidance_radius_m;
    if (radius <= 0.0) return;
    const Planar offset = other.position - walker.position;
    const double distance = length(offset);
    if (distance >= radius) return;
    const double closeness = 1.0 - distance / radius;
    const Planar toward_other =
        distance > 1e-9 ? (1.0 / distance) * offset : Planar{lower_index ? 1.0 : -1.0, 0.0};
    const double ahead = dot(walker.heading, toward_other);
    if (ahead > 0.0) {
      avoidance.turn_rate -=
          options_.avoidance_turn_rate_rad_s * closeness * sign_of(cross(walker.heading, toward_other));
      avoidance.braking = std::max(avoidance.braking, closeness * ahead);
    }
    avoidance.sidestep = avoidance.sidestep - (options_.avoidance_speed_m_s * closeness) * toward_other;
  }

  const SyntheticOptions& options_;
  RandomStream random_;
  int substeps_ = 1;
  double substep_ = 0.0;
  double turn_rate_memory_ = 0.0;      // φ
  double turn_rate_innovation_ = 0.0;  // σ_ω √(1 − φ²)
  double stop_probability_ = 0.0;      // per substep
  std::vector<Walker> walkers_;
};

// ── Measurements ──

std::string scene_name(std::string_view split, int index) {
  return fmt::format("synthetic-{}-{:04d}", split, index);
}

BenchmarkSplit make_split(const SyntheticOptions& options, std::span<const SyntheticView> views,
                          const RandomStream& root, std::string_view split_name) {
  BenchmarkSplit split;
  const RandomStream split_random = root.child(split_name);
  std::vector<std::string> object_ids;
  for (int object = 0; object < options.objects; ++object) object_ids.push_back(fmt::format("o{}", object));

  for (int scene_index = 0; scene_index < options.scenes; ++scene_index) {
    const std::string scene = scene_name(split_name, scene_index);
    const RandomStream scene_random = split_random.child(static_cast<std::uint64_t>(scene_index));
    const std::vector<std::vector<Planar>> positions =
        SceneMotion(options, scene_random.child("motion")).run();

    std::vector<RandomStream> sensing;
    const RandomStream sensing_root = scene_random.child("sensing");
    for (std::size_t view = 0; view < views.size(); ++view) sensing.push_back(sensing_root.child(view));

    for (int step = 0; step < options.steps; ++step) {
      const double time = static_cast<double>(step) / options.rate_hz;
      const std::vector<Planar>& frame = positions[static_cast<std::size_t>(step)];
      for (int object = 0; object < options.objects; ++object) {
        const Planar ground = frame[static_cast<std::size_t>(object)];
        split.truth.push_back(
            {scene, time, object_ids[static_cast<std::size_t>(object)], Vector3d(ground.x, ground.y, 0.0)});
      }
      for (std::size_t view = 0; view < views.size(); ++view) {
        RandomStream& random = sensing[view];
        for (int object = 0; object < options.objects; ++object) {
          const Planar ground = frame[static_cast<std::size_t>(object)];
          const Vector3d target(ground.x, ground.y, 0.0);
          const LineOfSightNoise noise = line_of_sight_noise(options, views[view], target);
          if (!random.bernoulli(detection_probability(options, noise.range))) continue;
          // One draw per statement: the order of evaluation of function arguments is unspecified.
          Vector3d standard_normal;
          for (int axis = 0; axis < 3; ++axis) standard_normal(axis) = random.normal();
          const Matrix3d root_of_covariance = noise.square_root();
          Vector3d measured;
          for (int row = 0; row < 3; ++row) {
            measured(row) = target(row) + (root_of_covariance(row, 0) * standard_normal(0) +
                                           root_of_covariance(row, 1) * standard_normal(1) +
                                           root_of_covariance(row, 2) * standard_normal(2));
          }
          split.measurements.push_back(
              {scene, time, views[view].id, object_ids[static_cast<std::size_t>(object)],
               Gaussian3::from_covariance(measured, noise.covariance()), views[view].sensor_position, std::nullopt});
        }
      }
    }
  }
  return split;
}

nlohmann::json options_json(const SyntheticOptions& options) {
  nlohmann::json described = {
      {"seed", options.seed},
      {"objects", options.objects},
      {"views", options.views},
      {"steps", options.steps},
      {"scenes", options.scenes},
      {"rate_hz", options.rate_hz},
      {"area_half_width_m", options.area_half_width_m},
      {"boundary_margin_m", options.boundary_margin_m},
      {"boundary_turn_rate_rad_s", options.boundary_turn_rate_rad_s},
      {"min_speed_m_s", options.min_speed_m_s},
      {"max_speed_m_s", options.max_speed_m_s},
      {"max_acceleration_m_s2", options.max_acceleration_m_s2},
      {"turn_rate_std_rad_s", options.turn_rate_std_rad_s},
      {"turn_rate_correlation_s", options.turn_rate_correlation_s},
      {"stop_rate_per_s", options.stop_rate_per_s},
      {"min_stop_s", options.min_stop_s},
      {"max_stop_s", options.max_stop_s},
      {"avoidance_radius_m", options.avoidance_radius_m},
      {"avoidance_turn_rate_rad_s", options.avoidance_turn_rate_rad_s},
      {"avoidance_speed_m_s", options.avoidance_speed_m_s},
      {"max_substep_s", options.max_substep_s},
      {"view_ring_radius_m", options.view_ring_radius_m},
      {"view_ring_jitter_m", options.view_ring_jitter_m},
  };
  described.update(view_noise_options_json(options));
  return described;
}

}  // namespace

void validate_synthetic_options(const SyntheticOptions& options) {
  const OptionChecks check("synthetic benchmark");
  check.whole("objects", options.objects, 1);
  check.whole("views", options.views, 1);
  check.whole("steps", options.steps, 2);
  check.whole("scenes", options.scenes, 1);
  check.size(static_cast<double>(options.scenes) * options.steps * options.objects * options.views,
             "scenes × steps × objects × views");
  check.positive("rate_hz", options.rate_hz);

  check.positive("area_half_width_m", options.area_half_width_m);
  check.real("boundary_margin_m", options.boundary_margin_m,
             options.boundary_margin_m > 0.0 && options.boundary_margin_m < options.area_half_width_m,
             "positive and less than area_half_width_m");
  check.not_negative("boundary_turn_rate_rad_s", options.boundary_turn_rate_rad_s);
  check.not_negative("min_speed_m_s", options.min_speed_m_s);
  check.not_negative("max_speed_m_s", options.max_speed_m_s);
  check.range("min_speed_m_s", options.min_speed_m_s, "max_speed_m_s", options.max_speed_m_s);
  check.positive("max_acceleration_m_s2", options.max_acceleration_m_s2);
  check.not_negative("turn_rate_std_rad_s", options.turn_rate_std_rad_s);
  check.positive("turn_rate_correlation_s", options.turn_rate_correlation_s);
  check.not_negative("stop_rate_per_s", options.stop_rate_per_s);
  check.not_negative("min_stop_s", options.min_stop_s);
  check.not_negative("max_stop_s", options.max_stop_s);
  check.range("min_stop_s", options.min_stop_s, "max_stop_s", options.max_stop_s);
  check.not_negative("avoidance_radius_m", options.avoidance_radius_m);
  check.not_negative("avoidance_turn_rate_rad_s", options.avoidance_turn_rate_rad_s);
  check.not_negative("avoidance_speed_m_s", options.avoidance_speed_m_s);
  check.positive("max_substep_s", options.max_substep_s);

  check.positive("view_ring_radius_m", options.view_ring_radius_m);
  check.real("view_ring_jitter_m", options.view_ring_jitter_m,
             options.view_ring_jitter_m >= 0.0 && options.view_ring_jitter_m < options.view_ring_radius_m,
             "zero or positive and less than view_ring_radius_m");
  check_view_noise_options(check, options);
  check_view_clock_options(check, options.clocks, 1.0 / options.rate_hz);
}

std::vector<SyntheticView> place_synthetic_views(const SyntheticOptions& options) {
  validate_synthetic_options(options);
  RandomStream random = RandomStream(options.seed).child("views");
  const double first_angle = random.uniform(0.0, kTwoPi);
  std::vector<SyntheticView> views;
  for (int index = 0; index < options.views; ++index) {
    const double angle = first_angle + kTwoPi * index / options.views +
                         random.uniform(-options.view_angle_jitter_rad, options.view_angle_jitter_rad);
    const double radius =
        options.view_ring_radius_m + random.uniform(-options.view_ring_jitter_m, options.view_ring_jitter_m);
    const double height = random.uniform(options.min_sensor_height_m, options.max_sensor_height_m);
    const double noise_scale = random.uniform(options.min_noise_scale, options.max_noise_scale);
    const portable::SineCosine direction = portable::sin_cos(angle);
    views.push_back({fmt::format("v{}", index),
                     Vector3d(radius * direction.cosine, radius * direction.sine, height), noise_scale});
  }
  return views;
}

LineOfSightNoise line_of_sight_noise(const SyntheticOptions& options, const SyntheticView& view,
                                     const Vector3d& target) {
  LineOfSightNoise noise = line_of_sight(view.sensor_position, target);
  const double range = noise.range;
  const double scale = view.noise_scale;
  noise.standard_deviations =
      Vector3d(scale * (options.range_noise_m + options.range_noise_per_m2 * (range * range)),
               scale * (options.cross_noise_m + options.cross_noise_per_m * range),
               scale * (options.vertical_noise_m + options.vertical_noise_per_m * range));
  return noise;
}

double detection_probability(const SyntheticOptions& options, double range_m) {
  return range_detection_probability(range_m, options.max_range_m, options.detection_probability_near,
                                     options.detection_probability_far);
}

nlohmann::json describe_synthetic_views(std::span<const SyntheticView> views) {
  nlohmann::json described = nlohmann::json::array();
  for (const SyntheticView& view : views) {
    described.push_back(
        {{"id", view.id},
         {"sensor_position", {view.sensor_position.x(), view.sensor_position.y(), view.sensor_position.z()}},
         {"noise_scale", view.noise_scale}});
  }
  return described;
}

nlohmann::json describe_synthetic_benchmark(const SyntheticOptions& options,
                                            std::span<const SyntheticView> views) {
  return {
      {"source", "synthetic"},
      {"seed", options.seed},
      {"options", options_json(options)},
      {"views", describe_synthetic_views(views)},
      {"motion_model",
       "ground-plane walkers, substeps of at most max_substep_s: Ornstein-Uhlenbeck turn rate "
       "(turn_rate_std_rad_s, turn_rate_correlation_s), random stops (stop_rate_per_s, "
       "uniform [min_stop_s, max_stop_s]), avoiding objects within "
       "avoidance_radius_m (turning, braking, sidestepping), turning back within boundary_margin_m of the "
       "square [-w, w]^2, velocity "
       "following the intended one with at most max_acceleration_m_s2; truth z = 0"},
      {"noise_model",
       "z = p + U diag(sigma) xi, xi ~ N(0, I), R = U diag(sigma^2) U^T with U = [range, horizontal "
       "across, vertical across] line-of-sight axes from the view's sensor; sigma_range = g (range_noise_m + "
       "range_noise_per_m2 r^2), sigma_across = g (cross_noise_m + cross_noise_per_m r), sigma_vertical = "
       "g (vertical_noise_m + vertical_noise_per_m r), g = the view's noise_scale; unbiased"},
      {"miss_model",
       "detected with probability P_near - (P_near - P_far) (r / max_range_m)^2 within max_range_m, "
       "never beyond; independent per view, object and step"},
  };
}

Benchmark make_synthetic_benchmark(const SyntheticOptions& options) {
  const std::vector<SyntheticView> views = place_synthetic_views(options);  // validates
  const RandomStream root(options.seed);
  Benchmark benchmark;
  benchmark.train = make_split(options, views, root, "train");
  benchmark.val = make_split(options, views, root, "val");
  benchmark.test = make_split(options, views, root, "test");
  benchmark.description = describe_synthetic_benchmark(options, views);
  if (options.clocks.active()) {
    // The walkers exist only during their scene: the tracks are extrapolated beyond it.
    const double period = 1.0 / options.rate_hz;
    nlohmann::json clocks = nlohmann::json::object();
    for (auto [name, split] : {std::pair{"train", &benchmark.train}, std::pair{"val", &benchmark.val},
                               std::pair{"test", &benchmark.test}}) {
      clocks[name] = apply_view_clocks(*split, options.clocks, period, root);
    }
    benchmark.description["clocks"] = view_clocks_json(options.clocks, period, std::move(clocks));
  }
  return benchmark;
}

}  // namespace stgf
