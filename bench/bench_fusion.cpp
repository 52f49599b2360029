// SPDX-License-Identifier: Apache-2.0
// Throughput of the fusion core, counted per object-view (one measurement of one object by one view).
//
//   build/bench/bench_fusion --benchmark_filter=. --benchmark_min_time=1
//
// BM_MultiViewUpdate/n: the multi-view update of DESIGN §1.3 for an object seen by n views (prior
//   plus n measurements → posterior); items = object-views.
// BM_MmtStep/n: one step of the `mmt` constant-velocity filter (predict, fuse n views, update);
//   items = object-views, so items/s at n = 1 is tracks updated per second.
// BM_MmtLocalizerStep: the whole `mmt` method on a step of 200 objects × 8 views, including the
//   grouping of measurements by object and the per-row output.
// BM_RegistrationStep/n: `ours`' registration handling (combine + learn) for 4 objects × n views.

#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "stgf/core/constant_velocity_filter.hpp"
#include "stgf/core/multi_view_update.hpp"
#include "stgf/core/view_registration.hpp"
#include "stgf/methods/multi_view_kalman_tracker.hpp"

namespace stgf {
namespace {

Matrix3d random_covariance(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Matrix3d a;
  for (int k = 0; k < 9; ++k) a(k) = uniform(rng);
  return scale * (a * a.transpose() + 0.5 * Matrix3d::Identity());
}

std::vector<Gaussian3> random_measurements(int count, std::mt19937_64& rng) {
  std::vector<Gaussian3> measurements;
  for (int k = 0; k < count; ++k) {
    measurements.push_back(Gaussian3::from_covariance(Vector3d::Random() * 10.0, random_covariance(rng, 0.2)));
  }
  return measurements;
}

void BM_MultiViewUpdate(benchmark::State& state) {
  const int views = static_cast<int>(state.range(0));
  std::mt19937_64 rng(1);
  // Many objects, so the loop is not served from a single cached object.
  constexpr int kObjects = 256;
  std::vector<Gaussian3> priors = random_measurements(kObjects, rng);
  std::vector<std::vector<Gaussian3>> measurements;
  for (int i = 0; i < kObjects; ++i) measurements.push_back(random_measurements(views, rng));
  int object = 0;
  for (auto _ : state) {
    Gaussian3 posterior = multi_view_update(priors[object], measurements[object]);
    benchmark::DoNotOptimize(posterior);
    object = (object + 1) % kObjects;
  }
  state.SetItemsProcessed(state.iterations() * views);
}
BENCHMARK(BM_MultiViewUpdate)->Arg(1)->Arg(2)->Arg(4)->Arg(7)->Arg(8);

void BM_MmtStep(benchmark::State& state) {
  const int views = static_cast<int>(state.range(0));
  std::mt19937_64 rng(2);
  constexpr int kObjects = 256;
  std::vector<ConstantVelocityFilter> filters;
  std::vector<std::vector<Gaussian3>> measurements;
  for (int i = 0; i < kObjects; ++i) {
    measurements.push_back(random_measurements(views, rng));
    filters.emplace_back(ConstantVelocityModel{}, measurements.back().front());
  }
  int object = 0;
  for (auto _ : state) {
    ConstantVelocityFilter& filter = filters[object];
    filter.predict(0.1);
    filter.update(measurements[object]);
    benchmark::DoNotOptimize(filter.state());
    object = (object + 1) % kObjects;
  }
  state.SetItemsProcessed(state.iterations() * views);
}
BENCHMARK(BM_MmtStep)->Arg(1)->Arg(4)->Arg(7);

void BM_MmtLocalizerStep(benchmark::State& state) {
  constexpr int kObjects = 200, kViews = 8;
  std::mt19937_64 rng(3);
  std::vector<Measurement> rows;
  for (int i = 0; i < kObjects; ++i) {
    for (int v = 0; v < kViews; ++v) {
      rows.push_back(Measurement{"scene", 0.0, "v" + std::to_string(v), "o" + std::to_string(i),
                                 Gaussian3::from_covariance(Vector3d::Random(), random_covariance(rng, 0.2)),
                                 std::nullopt});
    }
  }
  std::vector<const Measurement*> step;
  for (const Measurement& row : rows) step.push_back(&row);
  MultiViewKalmanTracker tracker{ConstantVelocityModel{}};
  double time = 0.0;
  for (auto _ : state) {
    auto estimates = tracker.step(time, step);
    benchmark::DoNotOptimize(estimates);
    time += 0.1;
  }
  state.SetItemsProcessed(state.iterations() * kObjects * kViews);
}
BENCHMARK(BM_MmtLocalizerStep);

// The registration handling of `ours` on one step of 4 objects seen by n views (the mpl shape at
// n = 7): combine() per object, then learn() from the step; items = object-views.
void BM_RegistrationStep(benchmark::State& state) {
  const int views = static_cast<int>(state.range(0));
  constexpr int kObjects = 4;
  std::mt19937_64 rng(5);
  std::vector<Measurement> rows;
  for (int i = 0; i < kObjects; ++i) {
    for (int v = 0; v < views; ++v) {
      rows.push_back(Measurement{"scene", 0.0, "v" + std::to_string(v), "o" + std::to_string(i),
                                 Gaussian3::from_covariance(Vector3d::Random(), random_covariance(rng, 0.01)),
                                 std::nullopt});
    }
  }
  RegistrationPrior prior;
  prior.translation_sigma = Vector3d(0.3, 0.3, 0.0);
  prior.noise_ratio = Vector3d::Constant(0.5);
  ViewRegistration registration(prior);
  std::vector<const Measurement*> step;
  for (const Measurement& row : rows) step.push_back(&row);
  registration.learn(step);  // every view known, as in the steady state of a scene
  for (auto _ : state) {
    for (int i = 0; i < kObjects; ++i) {
      const Gaussian3 combined = registration.combine(std::span(step).subspan(static_cast<std::size_t>(i * views),
                                                                             static_cast<std::size_t>(views)));
      benchmark::DoNotOptimize(combined);
    }
    registration.learn(step);
  }
  state.SetItemsProcessed(state.iterations() * kObjects * views);
}
BENCHMARK(BM_RegistrationStep)->Arg(2)->Arg(4)->Arg(7);

}  // namespace
}  // namespace stgf

BENCHMARK_MAIN();
