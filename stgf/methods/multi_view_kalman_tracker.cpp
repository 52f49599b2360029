// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/multi_view_kalman_tracker.hpp"

#include "stgf/core/multi_view_update.hpp"
#include "stgf/methods/object_groups.hpp"

namespace stgf {

std::vector<Gaussian3> MultiViewKalmanTracker::step(double time,
                                                    std::span<const Measurement* const> measurements) {
  return estimate_per_object(measurements, [&](const ObjectGroup& group) {
    auto it = tracks_.find(group.object);
    if (it == tracks_.end()) {
      const Gaussian3 fused = information_weighted_mean(group.measurements);
      it = tracks_.emplace(std::string(group.object), Track{ConstantVelocityFilter(model_, fused), time})
               .first;
    } else {
      Track& track = it->second;
      track.filter.predict(time - track.time);
      track.filter.update(group.measurements);
      track.time = time;
    }
    return it->second.filter.position();
  });
}

}  // namespace stgf
