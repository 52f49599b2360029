// SPDX-License-Identifier: Apache-2.0
// One step of `ours` as the filter runs it (core/scene_filter.hpp): every view's measurements of
// every object at one time go in, Φ forecasts the tracks that need it (the Eigen forward pass, one
// graph per scene), each object is predicted and updated with all its views, and every row's estimate
// comes out. Φ has the default shape (history 8, hidden 32) with untrained weights (its cost does not
// depend on the values); in-order data (no lag window, as `stgf run` without an arrival column).
//
//   build/bench/bench_ours_step --benchmark_min_time=1
//
// BM_OursStep/objects/views/registration: objects walk on circles around their own centres, spread
// over a square of side 2 √objects m; every view measures every object (R = 0.05² m² I, each view
// with its own offset). registration = 1 estimates the views' offsets jointly with the positions
// (the prior of the mpl benchmark), 0 turns that off. items = object-views.
//
// BM_OursAsynchronousFrame/objects/views/registration: the same frames with every view on its own
// clock — view v measures at (k + v / views) periods — each view's rows given as a message of their
// own, so a frame is `views` events of one view each (what `ours` meets on unsynchronised cameras or
// vehicles). Against BM_OursStep of the same shape it is the cost of the asynchronous engine per
// measurement.

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include <benchmark/benchmark.h>

#include "stgf/core/scene_filter.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf {
namespace {

constexpr double kPeriod = 0.1;  // s

// Steps of measurements (step → rows): 100, or fewer for large steps (at least 10, about 2 million
// rows in all); the filter starts again after them. `asynchronous`: view v measures v / views of a
// period after the step's time (its rows are in view order).
std::vector<std::vector<Measurement>> make_steps(int objects, int views, bool asynchronous = false) {
  const int steps_made = std::clamp(2'000'000 / (objects * views), 10, 100);
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double side = 2.0 * std::sqrt(static_cast<double>(objects));
  std::vector<Vector3d> centres, offsets;
  for (int i = 0; i < objects; ++i) centres.emplace_back(side * uniform(random), side * uniform(random), 0.0);
  for (int v = 0; v < views; ++v) offsets.emplace_back(0.05 * normal(random), 0.05 * normal(random), 0.0);
  const Matrix3d r = 0.05 * 0.05 * Matrix3d::Identity();
  std::vector<std::vector<Measurement>> steps(static_cast<std::size_t>(steps_made));
  for (int k = 0; k < steps_made; ++k) {
    for (int v = 0; v < views; ++v) {
      const double t = kPeriod * (k + (asynchronous ? static_cast<double>(v) / views : 0.0));
      for (int i = 0; i < objects; ++i) {
        const double phase = 0.5 * t + i;
        const Vector3d truth = centres[i] + Vector3d(std::cos(phase), std::sin(phase), 0.0);
        const Vector3d noise(0.05 * normal(random), 0.05 * normal(random), 0.05 * normal(random));
        steps[k].push_back(Measurement{"scene", t, "v" + std::to_string(v), "o" + std::to_string(i),
                                       Gaussian3::from_covariance(truth + offsets[v] + noise, r), std::nullopt});
      }
    }
  }
  return steps;
}

// One frame per iteration: given in one call, or (asynchronous) one call per view.
void run_frames(benchmark::State& state, bool asynchronous) {
  const int objects = static_cast<int>(state.range(0));
  const int views = static_cast<int>(state.range(1));
  FilterOptions options;
  options.lag_window = 0.0;
  if (state.range(2) != 0) {
    options.registration.translation_sigma = Vector3d(0.1, 0.1, 0.0);
    options.registration.noise_ratio = Vector3d::Constant(0.5);
  }
  const MotionModel model(MotionModelShape{}, MotionNormalisation{0.5, kPeriod, 5.0, 3 * kPeriod}, 1);
  // Google Benchmark calls this function several times per size: the steps are made once.
  static std::map<std::tuple<int, int, bool>, std::vector<std::vector<Measurement>>> made;
  const std::tuple<int, int, bool> shape{objects, views, asynchronous};
  if (!made.contains(shape)) {
    made.clear();  // one size at a time in memory
    made[shape] = make_steps(objects, views, asynchronous);
  }
  const std::vector<std::vector<Measurement>>& steps = made[shape];
  // Per step, its messages: the whole step, or each view's rows.
  const std::size_t per_message = asynchronous ? static_cast<std::size_t>(objects) : steps[0].size();
  std::vector<std::vector<std::vector<const Measurement*>>> messages(steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    for (std::size_t first = 0; first < steps[k].size(); first += per_message) {
      std::vector<const Measurement*>& message = messages[k].emplace_back();
      for (std::size_t row = first; row < first + per_message; ++row) message.push_back(&steps[k][row]);
    }
  }
  const std::vector<std::size_t> ids(per_message);
  auto filter = std::make_unique<SceneFilter>(model, options);
  std::size_t step = 0;
  std::vector<SceneFilter::Result> results;
  for (auto _ : state) {
    if (step == steps.size()) {
      state.PauseTiming();
      filter = std::make_unique<SceneFilter>(model, options);
      step = 0;
      state.ResumeTiming();
    }
    for (const std::vector<const Measurement*>& message : messages[step]) {
      filter->receive(message, ids);
      while (!filter->advance()) filter->provide_forecasts(model.forecast(filter->forecast_request()));
      filter->take_results(results);
      benchmark::DoNotOptimize(results.data());
    }
    ++step;
  }
  state.SetItemsProcessed(state.iterations() * objects * views);
}

void BM_OursStep(benchmark::State& state) { run_frames(state, false); }
void BM_OursAsynchronousFrame(benchmark::State& state) { run_frames(state, true); }

// The mpl shape, then the scaling table of bench/README.md: objects × views, registration off and on
// (an object's update costs O(k c + c²) in its k views and the scene's c offset coordinates).
BENCHMARK(BM_OursStep)
    ->Args({4, 7, 1})
    ->Args({4, 7, 0})
    ->ArgsProduct({{10, 100, 1000, 10000}, {1, 4, 16, 64}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);
// The mpl shape, and a larger scene, each view on its own clock.
BENCHMARK(BM_OursAsynchronousFrame)
    ->Args({4, 7, 1})
    ->Args({4, 7, 0})
    ->Args({100, 16, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace stgf

BENCHMARK_MAIN();
