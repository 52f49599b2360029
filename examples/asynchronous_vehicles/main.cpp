// SPDX-License-Identifier: Apache-2.0
// Two connected vehicles on their own clocks share what they see over a lossy, laggy link; the
// fuser takes each message when it arrives, late and out of order, and keeps one track per object.
//
//   build/examples/example_asynchronous_vehicles              # constant-velocity predictor
//   build/examples/example_asynchronous_vehicles MODEL.pt     # the learned Φ from `stgf train`
//
// Vehicle "ego" samples at 10 Hz from t = 0; vehicle "peer" samples at 10 Hz too, but its clock's
// frames fall 37 ms after ego's. Each sends one message per frame with every object it sees (a
// cyclist and a pedestrian), stamped with its measurement time. Ego's messages reach the fuser after
// 5–20 ms; peer's travel over V2X and arrive 40–180 ms late, so they often come after ego's next
// frame. One in ten of peer's messages is lost. Peer's GPS pose is off by (0.4, −0.3) m, which its R
// does not say: the filter learns the offset between the vehicles from how each one's measurements
// sit against the fused track (no two messages are ever at the same time), and corrects for it.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <random>

#include "stgf/model/trained_motion_model.hpp"
#include "stgf/model/registration_metadata.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"

namespace {

using stgf::Gaussian3;
using stgf::Matrix3d;
using stgf::Vector3d;

Vector3d truth_at(const std::string& object, double t) {
  if (object == "cyclist") return Vector3d(4.0 * t, 2.0 + 0.5 * std::sin(0.8 * t), 0.0);  // 4 m/s, weaving
  return Vector3d(10.0 - 1.2 * t, 6.0, 0.0);                                               // 1.2 m/s, straight
}

struct Message {
  double arrival;
  std::vector<stgf::Measurement> measurements;
};

int run(int argc, char** argv) {
  std::unique_ptr<stgf::MotionPredictor> predictor;
  stgf::FilterOptions options;
  options.lag_window = 0.5;  // messages up to 0.5 s late are fused in their place in time
  // Each vehicle's pose error is unknown but bounded: 0.5 m per ground axis, a little in height.
  options.registration.translation_sigma = Vector3d(0.5, 0.5, 0.05);
  if (argc > 1) {
    auto model = std::make_unique<stgf::TrainedMotionModel>(stgf::TrainedMotionModel::load(argv[1]));
    predictor = std::move(model);
  } else {
    // History positions a frame apart (0.09 s), as a learned model's come from its training rate.
    predictor = std::make_unique<stgf::ConstantVelocityPredictor>(/*q=*/2.0, /*speed=*/3.0, /*horizon=*/1.0,
                                                                  /*history_spacing=*/0.09);
  }
  stgf::SpatiotemporalGraphFilter filter(*predictor, options);

  // The messages, as the vehicles send them.
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform;
  const Vector3d peer_offset(0.4, -0.3, 0.0);
  std::vector<Message> messages;
  for (int frame = 0; frame < 40; ++frame) {
    for (const std::string vehicle : {"ego", "peer"}) {
      const bool peer = vehicle == "peer";
      const double t = 0.1 * frame + (peer ? 0.037 : 0.0);
      if (peer && uniform(random) < 0.1) continue;  // lost
      Message message{t + (peer ? 0.04 + 0.14 * uniform(random) : 0.005 + 0.015 * uniform(random)), {}};
      for (const std::string object : {"cyclist", "pedestrian"}) {
        // Depth noise along x for ego, along y for peer (they look from different sides).
        const Matrix3d r = peer ? Matrix3d(Vector3d(0.04, 0.25, 0.01).asDiagonal()) : Matrix3d(Vector3d(0.25, 0.04, 0.01).asDiagonal());
        const Vector3d noise(std::sqrt(r(0, 0)) * normal(random), std::sqrt(r(1, 1)) * normal(random),
                             std::sqrt(r(2, 2)) * normal(random));
        const Vector3d z = truth_at(object, t) + (peer ? peer_offset : Vector3d::Zero()) + noise;
        message.measurements.push_back({"road", t, vehicle, object, Gaussian3::from_covariance(z, r), std::nullopt, std::nullopt});
      }
      messages.push_back(std::move(message));
    }
  }
  // The fuser sees them in arrival order.
  std::stable_sort(messages.begin(), messages.end(),
                   [](const Message& a, const Message& b) { return a.arrival < b.arrival; });

  std::printf("arrival  measured  vehicle  object      error (m)  σ_x    σ_y   note\n");
  double latest = -1.0, squared_error = 0.0, measured_error = 0.0;
  int count = 0;
  for (const Message& message : messages) {
    const double t = message.measurements.front().time;
    const std::vector<Gaussian3> estimates = filter.fuse(message.measurements);  // one per measurement
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      const stgf::Measurement& m = message.measurements[k];
      const double error = (estimates[k].mean() - truth_at(m.object, t)).norm();
      if (t > 1.0) {  // after the first second, once the peer's offset is known
        squared_error += error * error;
        measured_error += (m.position.mean() - truth_at(m.object, t)).squaredNorm();
        ++count;
      }
      if (message.arrival < 1.0 || k > 0) continue;
      std::printf("%6.3f   %6.3f    %-7s  %-10s  %6.3f    %.3f  %.3f  %s\n", message.arrival, t, m.view.c_str(),
                  m.object.c_str(), error, std::sqrt(estimates[k].covariance()(0, 0)),
                  std::sqrt(estimates[k].covariance()(1, 1)), t < latest ? "late: fused in its place" : "");
    }
    latest = std::max(latest, t);
  }
  const Vector3d learnt = filter.registration_offset("peer").head<3>() - filter.registration_offset("ego").head<3>();
  std::printf("\nafter 1 s: RMS error of the live estimates %.3f m (of the measurements alone %.3f m)\n",
              std::sqrt(squared_error / count), std::sqrt(measured_error / count));
  std::printf("peer's offset relative to ego: learnt (%.2f, %.2f) m, true (%.2f, %.2f) m\n", learnt.x(), learnt.y(),
              peer_offset.x(), peer_offset.y());
  std::printf("messages fused in their place after later ones: %zu rewinds; too late for the window: %zu\n",
              filter.rewinds(), filter.late_measurements());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "example_asynchronous_vehicles: %s\n", error.what());
    return 2;
  }
}
