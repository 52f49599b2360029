// SPDX-License-Identifier: Apache-2.0
// Inference time of the learned motion model Φ for one step: every view's graph of the step goes
// through one batched forward pass (history 8, hidden 32, the default shape).
//
//   build/bench/bench_motion_model --benchmark_min_time=1
//
// BM_PhiStep/objects/views: one step of `views` graphs of `objects` objects each (all views see all
// objects). The Python STGAT reference takes about 1.2 ms per scene of 2–10 pedestrians for one
// prediction step on this kind of CPU. items = object-views predicted.

#include <cmath>

#include <benchmark/benchmark.h>
#include <torch/torch.h>

#include "stgf/learn/motion_model.hpp"

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

void BM_PhiStep(benchmark::State& state) {
  const int objects = static_cast<int>(state.range(0));
  const int views = static_cast<int>(state.range(1));
  torch::set_num_threads(1);
  const MotionModel model(MotionModelShape{}, MotionNormalisation{}, 1);
  const std::vector<MotionGraph> graphs = step_graphs(objects, views, MotionModelShape{}.history_length);
  for (auto _ : state) {
    auto predicted = model.predict(graphs);
    benchmark::DoNotOptimize(predicted);
  }
  state.SetItemsProcessed(state.iterations() * objects * views);
}
BENCHMARK(BM_PhiStep)->Args({4, 7})->Args({10, 1})->Args({200, 8})->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace stgf

BENCHMARK_MAIN();
