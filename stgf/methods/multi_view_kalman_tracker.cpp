// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/multi_view_kalman_tracker.hpp"

#include "stgf/core/multi_view_update.hpp"
#include "stgf/methods/object_groups.hpp"

namespace stgf {

std::vector<Gaussian3> MultiViewKalmanTracker::step(double time,
                                                    std::span<const Measurement* const> measurements) {
  return estimate_per_object(measurements, [&](const ObjectGroup& group) {
    auto it = tracks_.find(group.object);
    std::vector<double> distances;
    if (it != tracks_.end()) {
      it->second.filter.predict(time - it->second.time);
      it->second.time = time;
      if (gate_.enabled()) {
        const Gaussian3 predicted = it->second.filter.position();
        for (const Gaussian3& z : group.measurements) {
          distances.push_back(distance_squared(z.mean() - predicted.mean(), z.covariance() + predicted.covariance()));
        }
      }
    }
    const MeasurementGate::Decision decision =
        gate_.enabled() ? gate_.decide(distances, group.measurements, it == tracks_.end() ? 0 : it->second.gated_events)
                        : MeasurementGate::pass_all(group.measurements.size());
    // What is fused: every measurement, or (copied) those that passed the gate.
    std::span<const Gaussian3> fused = group.measurements;
    std::vector<Gaussian3> passing;
    if (decision.checked) {
      for (std::size_t k = 0; k < group.measurements.size(); ++k) {
        counts_.count(group.views[k], decision.passes[k]);
        if (decision.passes[k]) passing.push_back(group.measurements[k]);
      }
      fused = passing;
    }
    if (decision.restart) {
      tracks_.erase(it);
      it = tracks_.end();
      ++restarts_;
    }
    if (it == tracks_.end()) {
      it = tracks_.emplace(std::string(group.object),
                           Track{ConstantVelocityFilter(model_, information_weighted_mean(fused)), time, 0})
               .first;
    } else if (fused.empty()) {
      ++it->second.gated_events;
    } else {
      it->second.filter.update(fused);
      it->second.gated_events = 0;
    }
    return it->second.filter.position();
  });
}

void MultiViewKalmanTracker::report_gating(const std::string& scene, GatingSummary& summary) const {
  summary.add(scene, counts_);
  summary.restarts += restarts_;
}

}  // namespace stgf
