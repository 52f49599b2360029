// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whether a scene's sensors stand still (fixed cameras, roadside units) or move (connected vehicles),
// as far as the rows tell: where the registration prior's scales are learned across scenes depends on
// it (design §1.7, registration_scale_pool.hpp).
//
// Why it matters. A view's unstated offset is modelled as t + L δ + ε (view_registration.hpp): a
// translation, a small turn in the view's own noise units, and a scatter. A moving platform shares its
// detections through its own pose estimate (GPS, odometry), so its error is a rigid pose error — a
// translation and a heading error, the latter across each ray in proportion to range, as a range
// sensor's noise across the ray is — which that model holds. A fixed camera's calibration error,
// back-projected onto the ground, is not rigid: a height error moves ground points along their rays in
// proportion to range, which the model lacks, and a thousand scenes' disagreements then widen the
// prior beyond the offsets' size (design §1.7, "Where the summed disagreements go wrong").
//
// Rule. A scene's sensors move when some view reports, within the scene, a sensor position more than
// kMovingSensorDistance from its first (a vehicle at 1 m/s over one second does; a surveyed camera, or
// a parked vehicle, does not). Rows without a sensor position count as fixed.

#include <cstddef>
#include <functional>
#include <map>
#include <span>
#include <string>

#include "stgf/core/records.hpp"
#include "stgf/core/steps.hpp"

namespace stgf {

enum class SensorMotion { kFixed, kMoving };

inline constexpr double kMovingSensorDistance = 0.5;  // m

// Of a scene of `measurements` (its rows: Scene::steps).
SensorMotion sensor_motion(std::span<const Measurement> measurements, const Scene& scene);

// The same rule row by row, for a scene whose rows are not all known yet (a streaming filter): fixed
// until some view's sensor has been seen more than kMovingSensorDistance from where it was first seen.
class SensorMotionWatch {
 public:
  void see(const Measurement& measurement);
  SensorMotion motion() const { return motion_; }

 private:
  std::map<std::string, Vector3d, std::less<>> first_position_;  // of each view that gave one
  SensorMotion motion_ = SensorMotion::kFixed;
};

// One T for scenes of fixed sensors and one for scenes whose sensors move.
template <class T>
struct PerSensorMotion {
  T fixed{};
  T moving{};
  T& operator[](SensorMotion motion) { return motion == SensorMotion::kMoving ? moving : fixed; }
  const T& operator[](SensorMotion motion) const { return motion == SensorMotion::kMoving ? moving : fixed; }
};

inline constexpr SensorMotion kSensorMotions[] = {SensorMotion::kFixed, SensorMotion::kMoving};

}  // namespace stgf
