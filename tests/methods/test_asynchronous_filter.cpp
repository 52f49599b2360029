// SPDX-License-Identifier: Apache-2.0
// The filter on views with their own clocks and late messages (core/scene_filter.hpp): separate calls
// at one time are one multi-view update; any arrival order within the lag window ends in the state of
// in-order delivery; a message older than the window is counted and left out, or stops; registration
// offsets are learnt when no two views ever measure at the same time; row order within a time does
// not matter.

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/run_method.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"
#include "support/test_predictors.hpp"

namespace stgf {
namespace {

// Three views (their own phases within a 0.1 s frame) watching two objects that walk in circles;
// each view has a fixed offset its R does not state.
struct Stream {
  std::vector<Measurement> rows;  // in time order
  std::map<std::string, Vector3d> offsets;
};

Vector3d truth_at(const std::string& object, double t) {
  const double radius = object == "o" ? 4.0 : 6.0;
  return Vector3d(radius * std::cos(0.3 * t), radius * std::sin(0.3 * t), 0.0);
}

Stream make_stream(int frames, bool asynchronous, std::uint64_t seed) {
  Stream stream;
  stream.offsets = {{"a", Vector3d(0.3, -0.2, 0.0)}, {"b", Vector3d(-0.1, 0.25, 0.0)}, {"c", Vector3d(0.0, 0.0, 0.0)}};
  const std::map<std::string, double> phases = {{"a", 0.0}, {"b", asynchronous ? 0.031 : 0.0}, {"c", asynchronous ? 0.067 : 0.0}};
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  for (int k = 0; k < frames; ++k) {
    for (const auto& [view, phase] : phases) {
      const double t = 0.1 * k + phase;
      for (const std::string object : {"o", "p"}) {
        Matrix3d r = Vector3d(0.02, 0.05, 0.01).asDiagonal();
        if (view == "b") r = Vector3d(0.05, 0.02, 0.01).asDiagonal();
        const Vector3d noise(std::sqrt(r(0, 0)) * normal(random), std::sqrt(r(1, 1)) * normal(random),
                             std::sqrt(r(2, 2)) * normal(random));
        const Vector3d z = truth_at(object, t) + stream.offsets.at(view) + noise;
        stream.rows.push_back(Measurement{"s", t, view, object, Gaussian3::from_covariance(z, r), std::nullopt});
      }
    }
  }
  std::stable_sort(stream.rows.begin(), stream.rows.end(),
                   [](const Measurement& x, const Measurement& y) { return x.time < y.time; });
  return stream;
}

FilterOptions options_with_registration() {
  FilterOptions options;
  options.registration = RegistrationPrior{Vector3d(0.3, 0.3, 0.05), Vector3d::Constant(0.2)};
  return options;
}

// A probe at the end: the estimates a filter gives two new measurements tell its whole state.
std::vector<Gaussian3> probe(SpatiotemporalGraphFilter& filter, double time) {
  const Matrix3d r = 0.03 * Matrix3d::Identity();
  return filter.fuse(std::vector<Measurement>{
      {"s", time, "a", "o", Gaussian3::from_covariance(truth_at("o", time), r), std::nullopt},
      {"s", time, "c", "p", Gaussian3::from_covariance(truth_at("p", time), r), std::nullopt}});
}

void expect_same(const std::vector<Gaussian3>& a, const std::vector<Gaussian3>& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_LE((a[k].mean() - b[k].mean()).norm(), tolerance) << "estimate " << k;
    EXPECT_LE((a[k].covariance() - b[k].covariance()).norm(), tolerance) << "estimate " << k;
  }
}

const ConstantVelocityPredictor kPredictor(0.5, 1.0, /*horizon=*/2.0, /*history_spacing=*/0.09);

TEST(AsynchronousFilter, SeparateCallsAtOneTimeAreOneMultiViewUpdate) {
  const Stream stream = make_stream(20, /*asynchronous=*/false, 3);
  SpatiotemporalGraphFilter together(kPredictor, options_with_registration());
  SpatiotemporalGraphFilter apart(kPredictor, options_with_registration());
  for (std::size_t first = 0; first < stream.rows.size();) {
    std::size_t end = first;
    while (end < stream.rows.size() && stream.rows[end].time == stream.rows[first].time) ++end;
    const std::span<const Measurement> step(stream.rows.data() + first, end - first);
    const std::vector<Gaussian3> joint = together.fuse(step);
    // One call per view, in reverse view order: each returns the live estimate, never a NaN.
    std::vector<Gaussian3> last;
    for (std::size_t k = step.size(); k-- > 0;) {
      last = apart.fuse(step.subspan(k, 1));
      ASSERT_TRUE(last[0].mean().allFinite());
    }
    // The last call's estimate has every view of its time in it.
    EXPECT_LE((last[0].mean() - joint[0].mean()).norm(), 1e-9);
    first = end;
  }
  expect_same(probe(apart, 2.05), probe(together, 2.05), 1e-9);
}

TEST(AsynchronousFilter, AnyArrivalOrderWithinTheWindowEndsInTheInOrderState) {
  const Stream stream = make_stream(25, /*asynchronous=*/true, 5);
  SpatiotemporalGraphFilter in_order(kPredictor, options_with_registration());
  std::vector<Gaussian3> in_order_estimates;
  for (const Measurement& row : stream.rows) in_order_estimates.push_back(in_order.fuse(std::span(&row, 1))[0]);
  const std::vector<Gaussian3> reference = probe(in_order, 2.6);

  for (std::uint64_t seed : {1, 2, 3}) {
    // Each row arrives up to 0.3 s after it was measured (window 1 s).
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<double> latency(0.0, 0.3);
    std::vector<std::pair<double, std::size_t>> arrivals;
    for (std::size_t k = 0; k < stream.rows.size(); ++k) arrivals.emplace_back(stream.rows[k].time + latency(random), k);
    std::sort(arrivals.begin(), arrivals.end());
    SpatiotemporalGraphFilter shuffled(kPredictor, options_with_registration());
    double latest = -1.0;
    std::size_t late_rows_checked = 0;
    std::vector<bool> arrived(stream.rows.size(), false);
    for (const auto& [arrival, k] : arrivals) {
      const Gaussian3 estimate = shuffled.fuse(std::span(&stream.rows[k], 1))[0];
      // A row that arrives after exactly the rows in-order delivery had fused by its time (every row
      // measured before it, and those of its own time listed before it) gets the in-order answer.
      bool same_knowledge = true;
      for (std::size_t j = 0; j < stream.rows.size(); ++j) {
        if (j == k || stream.rows[j].time > stream.rows[k].time) continue;
        if (arrived[j] != (j < k)) same_knowledge = false;
      }
      if (same_knowledge && stream.rows[k].time < latest) {
        EXPECT_LE((estimate.mean() - in_order_estimates[k].mean()).norm(), 1e-9) << "row " << k;
        ++late_rows_checked;
      }
      arrived[k] = true;
      latest = std::max(latest, stream.rows[k].time);
    }
    EXPECT_GT(late_rows_checked, 10u);
    EXPECT_EQ(shuffled.late_measurements(), 0u);
    expect_same(probe(shuffled, 2.6), reference, 1e-9);
  }
}

TEST(AsynchronousFilter, AMessageOlderThanTheWindowIsCountedAndLeftOutOrStops) {
  const Stream stream = make_stream(30, /*asynchronous=*/true, 7);
  FilterOptions options;
  options.lag_window = 0.5;
  SpatiotemporalGraphFilter with_late(kPredictor, options), without(kPredictor, options);
  for (const Measurement& row : stream.rows) {
    if (row.time > 1.0) continue;
    with_late.fuse(std::span(&row, 1));
    without.fuse(std::span(&row, 1));
  }
  Measurement old = stream.rows.front();
  old.time = 0.2;  // 0.8 s before the latest
  old.view = "d";
  const Gaussian3 estimate = with_late.fuse(std::span(&old, 1))[0];
  EXPECT_EQ(with_late.late_measurements(), 1u);
  EXPECT_EQ(estimate.mean(), old.position.mean());  // its own measurement (no registration prior)
  expect_same(probe(with_late, 1.1), probe(without, 1.1), 0.0);

  options.late = LatePolicy::kStop;
  SpatiotemporalGraphFilter stopping(kPredictor, options);
  for (const Measurement& row : stream.rows) {
    if (row.time <= 1.0) stopping.fuse(std::span(&row, 1));
  }
  EXPECT_THROW(stopping.fuse(std::span(&old, 1)), LateMeasurementError);
  old.time = 0.6;  // within the window
  EXPECT_NO_THROW(stopping.fuse(std::span(&old, 1)));
}

TEST(AsynchronousFilter, BadInputIsRejectedAndChangesNothing) {
  SpatiotemporalGraphFilter filter(kPredictor);
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  Measurement row{"s", 0.0, "a", "o", Gaussian3::from_covariance(Vector3d::Zero(), r), std::nullopt};
  filter.fuse(std::span(&row, 1));
  EXPECT_THROW(filter.fuse(std::span(&row, 1)), std::invalid_argument);  // (a, o) twice at t = 0
  row.time = std::nan("");
  EXPECT_THROW(filter.fuse(std::span(&row, 1)), std::invalid_argument);
  row.time = 0.1;
  EXPECT_TRUE(filter.fuse(std::span(&row, 1))[0].mean().allFinite());
}

// No two views ever measure at the same time; the relative offsets are still learnt.
TEST(AsynchronousFilter, RegistrationOffsetsConvergeOnAsynchronousViews) {
  const Stream stream = make_stream(150, /*asynchronous=*/true, 11);
  SpatiotemporalGraphFilter filter(kPredictor, options_with_registration());
  filter.fuse(stream.rows);
  const auto translation = [&](const char* view) { return Vector3d(filter.registration_offset(view).head<3>()); };
  for (const auto& [u, w] : std::vector<std::pair<const char*, const char*>>{{"a", "b"}, {"a", "c"}, {"b", "c"}}) {
    const Vector3d estimated = translation(u) - translation(w);
    const Vector3d truth = stream.offsets.at(u) - stream.offsets.at(w);
    EXPECT_LT((estimated - truth).head<2>().norm(), 0.08) << u << " − " << w << ": " << estimated.transpose();
  }
  // Without any learning the corrections would stay zero.
  EXPECT_GT((translation("a") - translation("b")).norm(), 0.2);
}

TEST(AsynchronousFilter, RowOrderWithinATimeDoesNotMatter) {
  Stream stream = make_stream(15, /*asynchronous=*/false, 13);
  const FilterRun forward = run_spatiotemporal_graph_filter(kPredictor, options_with_registration(), stream.rows);
  std::vector<std::size_t> order(stream.rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::reverse(order.begin(), order.end());
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return stream.rows[a].time < stream.rows[b].time; });
  std::vector<Measurement> reordered;
  for (std::size_t k : order) reordered.push_back(stream.rows[k]);
  const FilterRun backward = run_spatiotemporal_graph_filter(kPredictor, options_with_registration(), reordered);
  for (std::size_t i = 0; i < order.size(); ++i) {
    EXPECT_EQ(backward.estimates[i].mean(), forward.estimates[order[i]].mean());
    EXPECT_EQ(backward.estimates[i].covariance(), forward.estimates[order[i]].covariance());
  }
}

// Φ reads velocities over the intervals it trained on: a track's history positions are at least the
// predictor's history spacing apart, even when two views measure the object microseconds apart just
// as a frame's window ends (the later one closes the frame on the earlier one's state, and opens the
// next frame, whose state would otherwise become a history position microseconds after it).
TEST(AsynchronousFilter, HistoryPositionsAreAHistorySpacingApart) {
  // Records the intervals between the history positions of every forecast it is asked for.
  class RecordingPredictor final : public testing::ForwardingPredictor {
   public:
    RecordingPredictor() : ForwardingPredictor(0.5, 1.0, 2.0, /*history_spacing=*/0.09) {}
    std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
      for (const MotionGraph& graph : graphs) {
        for (const ObjectHistory& history : graph.objects) {
          for (std::size_t k = 1; k < history.times.size(); ++k) spacings.push_back(history.times[k] - history.times[k - 1]);
        }
      }
      return ForwardingPredictor::forecast(graphs);
    }
    mutable std::vector<double> spacings;
  } predictor;
  // Views a, b and c measure "o" on their own clocks; at 0.0899 and 0.0901, b and c straddle the end
  // of the frame that a opened at 0.
  std::vector<Measurement> rows;
  const Matrix3d r = 0.01 * Matrix3d::Identity();
  for (const auto& [view, time] : std::vector<std::pair<std::string, double>>{
           {"a", 0.0}, {"b", 0.0899}, {"c", 0.0901}, {"a", 0.2}, {"b", 0.3}, {"c", 0.4}, {"a", 0.5}, {"b", 0.6}}) {
    rows.push_back(Measurement{"s", time, view, "o", Gaussian3::from_covariance(truth_at("o", time), r), std::nullopt});
  }
  const FilterRun run = run_spatiotemporal_graph_filter(predictor, FilterOptions{}, rows);
  ASSERT_FALSE(predictor.spacings.empty());
  for (const double spacing : predictor.spacings) EXPECT_GE(spacing, predictor.history_spacing());
  for (const Gaussian3& estimate : run.estimates) EXPECT_TRUE(estimate.mean().allFinite());
}

// The runner with an arrival column: the same as the streaming filter fed in arrival order.
TEST(AsynchronousFilter, RunnerWithArrivalsMatchesTheStreamingFilter) {
  Stream stream = make_stream(20, /*asynchronous=*/true, 17);
  std::mt19937_64 random(2);
  std::uniform_real_distribution<double> latency(0.0, 0.15);
  for (Measurement& row : stream.rows) row.arrival = row.time + latency(random);
  const FilterRun run = run_spatiotemporal_graph_filter(kPredictor, options_with_registration(), stream.rows);
  EXPECT_GT(run.rewinds, 0u);
  // Late: a row whose time is before that of a row that arrived before it.
  std::size_t late = 0;
  for (const Measurement& row : stream.rows) {
    for (const Measurement& earlier : stream.rows) {
      if (*earlier.arrival < *row.arrival && earlier.time > row.time + kSameStepTolerance) {
        ++late;
        break;
      }
    }
  }
  EXPECT_GT(late, 0u);
  EXPECT_EQ(run.late_rows, late);
  std::vector<std::size_t> order(stream.rows.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return *stream.rows[a].arrival < *stream.rows[b].arrival; });
  SpatiotemporalGraphFilter filter(kPredictor, options_with_registration());
  for (std::size_t k : order) {
    const Gaussian3 estimate = filter.fuse(std::span(&stream.rows[k], 1))[0];
    EXPECT_LE((estimate.mean() - run.estimates[k].mean()).norm(), 1e-12) << "row " << k;
  }
  // The runner lets what a late row sends back wait for the next rows (SceneFilter::Advance): it
  // goes back less often than the streaming filter, which processes everything each time.
  EXPECT_EQ(filter.late_rows(), run.late_rows);
  EXPECT_LT(run.rewinds, filter.rewinds());
  // Without arrival times, rows are fused in time order: a different, better-informed answer.
  std::vector<Measurement> in_time = stream.rows;
  for (Measurement& row : in_time) row.arrival.reset();
  EXPECT_EQ(run_spatiotemporal_graph_filter(kPredictor, options_with_registration(), in_time).rewinds, 0u);
  stream.rows.front().arrival.reset();
  EXPECT_THROW(run_spatiotemporal_graph_filter(kPredictor, {}, stream.rows), std::invalid_argument);
}

// mmt (a constant-velocity Kalman filter) on rows whose views never share a time: finite, and better
// than fusing each time alone (wls).
TEST(AsynchronousFilter, MmtHandlesAsynchronousRows) {
  const Stream stream = make_stream(40, /*asynchronous=*/true, 19);
  const std::vector<Gaussian3> mmt = run_method("mmt", MethodConfig{}, stream.rows);
  const std::vector<Gaussian3> wls = run_method("wls", MethodConfig{}, stream.rows);
  double mmt_error = 0.0, wls_error = 0.0;
  for (std::size_t k = 0; k < stream.rows.size(); ++k) {
    ASSERT_TRUE(mmt[k].mean().allFinite());
    const Vector3d truth = truth_at(stream.rows[k].object, stream.rows[k].time) + Vector3d::Zero();
    mmt_error += (mmt[k].mean() - truth).norm();
    wls_error += (wls[k].mean() - truth).norm();
  }
  EXPECT_LT(mmt_error, wls_error);
}

}  // namespace
}  // namespace stgf
