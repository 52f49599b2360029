// SPDX-License-Identifier: Apache-2.0
// Streaming use of the spatiotemporal graph filter, without files: a robot's loop hands the filter
// the measurements of each step as they arrive and gets one fused estimate per measurement back.
//
//   build/examples/example_streaming_filter              # constant-velocity predictor
//   build/examples/example_streaming_filter MODEL.pt     # the learned Φ from `stgf train`
//
// Two fixed cameras watch one pedestrian walking a quarter circle. Camera "east" sees well along
// x and poorly along y, camera "north" the other way round; "north" only comes online at step 5,
// and step 8 has no measurement at all (both cameras dropped a frame).

#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <random>

#include "stgf/model/trained_motion_model.hpp"
#include "stgf/model/registration_metadata.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"

namespace {

int run(int argc, char** argv) {
  using stgf::Gaussian3;
  using stgf::Matrix3d;
  using stgf::Vector3d;

  // The motion model: Φ from a model file, or constant velocity (Q = 0.5 m²/s² · Δt²).
  // The views' registration error (offsets their R does not state, such as a camera's calibration
  // error): a model file carries the prior calibrated at training. The simulated cameras below have
  // none, so without a model the prior stays zero (every R trusted as it is); for real cameras set
  // one, e.g. registration.translation_sigma = Vector3d(0.1, 0.1, 0.0) for 10 cm on the ground.
  std::unique_ptr<stgf::MotionPredictor> predictor;
  stgf::RegistrationPrior registration;
  if (argc > 1) {
    auto model = std::make_unique<stgf::TrainedMotionModel>(stgf::TrainedMotionModel::load(argv[1]));
    registration = stgf::registration_prior_from_metadata(model->metadata(), argv[1]).value_or(registration);
    predictor = std::move(model);
  } else {
    predictor = std::make_unique<stgf::ConstantVelocityPredictor>(0.5, 1.4);
  }
  stgf::FilterOptions options;
  options.registration = registration;
  stgf::SpatiotemporalGraphFilter filter(*predictor, options);  // one filter per scene

  // Each camera's noise: 5 cm along its good axis, 40 cm along its poor one.
  const Matrix3d east_noise = Vector3d(0.05 * 0.05, 0.4 * 0.4, 0.05 * 0.05).asDiagonal();
  const Matrix3d north_noise = Vector3d(0.4 * 0.4, 0.05 * 0.05, 0.05 * 0.05).asDiagonal();
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const auto noisy = [&](const Vector3d& truth, const Matrix3d& covariance) {
    const Vector3d unit(normal(random), normal(random), normal(random));
    return Vector3d(truth + covariance.cwiseSqrt() * unit);  // diagonal covariances: √ per axis
  };

  std::printf("step  time   view   truth (x, y)      estimate (x, y)    σx     σy\n");
  const double rate_hz = 5.0;
  for (int k = 0; k < 15; ++k) {
    const double t = k / rate_hz;
    const double angle = 0.1 * t;  // a slow turn on a 12 m circle
    const Vector3d truth(12.0 * std::sin(angle), 12.0 * (1.0 - std::cos(angle)), 0.0);

    // The measurements of this step, each describing itself (scene, time, view, object, z, R; no
    // sensor position, no arrival time).
    std::vector<stgf::Measurement> step;
    if (k != 8) {
      step.push_back({"demo", t, "east", "walker", Gaussian3::from_covariance(noisy(truth, east_noise), east_noise),
                      std::nullopt, std::nullopt});
      if (k >= 5) {
        step.push_back({"demo", t, "north", "walker",
                        Gaussian3::from_covariance(noisy(truth, north_noise), north_noise), std::nullopt,
                        std::nullopt});
      }
    }
    std::vector<const stgf::Measurement*> rows;
    for (const stgf::Measurement& measurement : step) rows.push_back(&measurement);

    const std::vector<Gaussian3> estimates = filter.step(t, rows);  // one per row, same order
    if (estimates.empty()) std::printf("%4d  %4.1f   (no measurement)\n", k, t);
    for (std::size_t i = 0; i < estimates.size(); ++i) {
      const Gaussian3& e = estimates[i];
      std::printf("%4d  %4.1f   %-5s  (%6.3f, %6.3f)  (%6.3f, %6.3f)  %.3f  %.3f\n", k, t, step[i].view.c_str(),
                  truth.x(), truth.y(), e.mean().x(), e.mean().y(), std::sqrt(e.covariance()(0, 0)),
                  std::sqrt(e.covariance()(1, 1)));
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "example_streaming_filter: %s\n", error.what());
    return 2;
  }
}
