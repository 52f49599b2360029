// SPDX-License-Identifier: Apache-2.0
// Inference time of the learned motion model Φ for one step (history 8, hidden 32, the default shape):
// the Eigen forward pass the filter runs, and the LibTorch network it replaced for inference.
//
//   build/bench/bench_motion_model --benchmark_min_time=1
//
// BM_PhiStep/objects/views: one step of `views` graphs of `objects` objects each (all views see all
// objects; the filter's one track per object makes one graph per scene: views = 1). The Python STGAT reference takes about 1.2 ms per scene of 2–10 pedestrians for one
// prediction step on this kind of CPU. items = object-views predicted.

#include <cmath>

#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include "stgf/learn/motion_model.hpp"
#include "stgf/learn/motion_network.hpp"

namespace stgf {
namespace {

std::vector<MotionGraph> step_graphs(int objects, int views, int history) {
  std::vector<MotionGraph> graphs;
  for (int v = 0; v < views; ++v) {
    MotionGraph graph{"scene", "v" + std::to_string(v), 0.1 * (history + 1), {}};
    for (int i = 0; i < objects; ++i) {
      ObjectHistory object{"o" + std::to_string(i), {}, {}};
      for (int k = 0; k <= history; ++k) {
        const double t = 0.1 * k;
        object.positions.emplace_back(0.3 * i + std::cos(t + i), 0.2 * i + std::sin(t + v), 0.0);
        object.times.push_back(t);
      }
      graph.objects.push_back(std::move(object));
    }
    graphs.push_back(std::move(graph));
  }
  return graphs;
}

// (objects, graphs) of a step: one scene of the mpl shape, its 7 per-view graphs, and larger ones
// (above 16 objects each object attends to its 8 nearest).
void step_sizes(benchmark::internal::Benchmark* benchmark) {
  for (const auto& [objects, graphs] : {std::pair{4, 1}, {4, 7}, {10, 1}, {200, 8}, {1000, 1}}) {
    benchmark->Args({objects, graphs});
  }
  benchmark->Unit(benchmark::kMicrosecond);
}

// Φ's forecast as the filter runs it: the Eigen forward pass (motion_inference.hpp).
void BM_PhiStep(benchmark::State& state) {
  const int objects = static_cast<int>(state.range(0));
  const int views = static_cast<int>(state.range(1));
  const MotionModel model(MotionModelShape{}, MotionNormalisation{}, 1);
  const std::vector<MotionGraph> graphs = step_graphs(objects, views, MotionModelShape{}.history_length);
  for (auto _ : state) {
    auto forecasts = model.forecast(graphs);
    benchmark::DoNotOptimize(forecasts);
  }
  state.SetItemsProcessed(state.iterations() * objects * views);
}
BENCHMARK(BM_PhiStep)->Apply(step_sizes);

// The same forward pass through the LibTorch network (what inference ran before; training still does).
void BM_PhiStepLibTorch(benchmark::State& state) {
  const int objects = static_cast<int>(state.range(0));
  const int views = static_cast<int>(state.range(1));
  torch::set_num_threads(1);
  MotionModel model(MotionModelShape{}, MotionNormalisation{}, 1);
  const std::vector<MotionGraph> graphs = step_graphs(objects, views, MotionModelShape{}.history_length);
  model.impl().network->eval();
  for (auto _ : state) {
    c10::InferenceMode inference;
    const detail::MotionBatch batch = detail::make_motion_batch(graphs, model.shape(), model.normalisation());
    auto acceleration = model.impl().network->acceleration(batch);
    benchmark::DoNotOptimize(acceleration);
  }
  state.SetItemsProcessed(state.iterations() * objects * views);
}
BENCHMARK(BM_PhiStepLibTorch)->Apply(step_sizes);

}  // namespace
}  // namespace stgf

BENCHMARK_MAIN();
