// SPDX-License-Identifier: Apache-2.0
#pragma once
// The network of Φ in LibTorch (see motion_model.hpp for the math). Private to the learn layer:
// only motion_model.cpp and motion_training.cpp include it, so LibTorch stays out of public headers.

#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "stgf/core/process_noise_curve.hpp"
#include "stgf/model/motion_features.hpp"
#include "stgf/model/motion_inference.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf::detail {

// A batch of graphs: Φ's inputs (motion_features.hpp) and the same numbers as LibTorch tensors.
struct MotionBatch : MotionFeatures {
  struct Tensors {
    torch::Tensor motion;         // [N, H, 7]
    torch::Tensor last_velocity;  // [N, 3]
    torch::Tensor horizon;        // [N, 1]
    torch::Tensor last_interval;  // [N, 1]
    torch::Tensor edge_source;    // [E] int64
    torch::Tensor edge_target;    // [E] int64
    torch::Tensor edge_offset;    // [E, 3]
  } tensors;
};

MotionBatch make_motion_batch(std::span<const MotionGraph> graphs, const MotionModelShape& shape,
                              const MotionNormalisation& normalisation);

class GraphAttentionImpl : public torch::nn::Module {
 public:
  GraphAttentionImpl(int in_features, int out_features);
  // h: [N, in] → [N, out]; attention over the edges (j → i) given as source/target lists.
  torch::Tensor forward(const torch::Tensor& h, const torch::Tensor& source, const torch::Tensor& target,
                        const torch::Tensor& offset);

 private:
  torch::nn::Linear transform_{nullptr};       // W
  torch::nn::Linear offset_transform_{nullptr};  // U
  torch::nn::Linear score_self_{nullptr};      // a_self
  torch::nn::Linear score_message_{nullptr};   // a_msg
};
TORCH_MODULE(GraphAttention);

class MotionNetworkImpl : public torch::nn::Module {
 public:
  explicit MotionNetworkImpl(const MotionModelShape& shape);
  // The predicted velocity over the coming interval, scaled by s_v: [N, 3].
  torch::Tensor forward(const MotionBatch& batch);
  // The head's output â in units of s_v / s_t: [N, 3]. It does not depend on the horizon:
  // forward = last_velocity + acceleration · (last_interval + horizon) / 2.
  torch::Tensor acceleration(const MotionBatch& batch);

 private:
  torch::nn::Linear embed_{nullptr};
  torch::nn::LSTM encoder_{nullptr};
  GraphAttention attention1_{nullptr};
  GraphAttention attention2_{nullptr};
  torch::nn::LSTMCell decoder_{nullptr};
  torch::nn::Linear head_{nullptr};
};
TORCH_MODULE(MotionNetwork);

}  // namespace stgf::detail

namespace stgf {

struct MotionModel::Impl {
  MotionModelShape shape;
  MotionNormalisation normalisation;
  detail::MotionNetwork network{nullptr};
  Matrix3d process_noise_reference = 0.01 * Matrix3d::Identity();  // Q_ref (m²)
  double process_noise_period = 0.1;                                // Δt_ref (s)
  std::vector<IntervalNoise> process_noise_intervals;               // Q beyond Δt_ref (may be empty)
  std::vector<IntervalNoise> coasting_process_noise;                // Q of a coasting track (may be empty)
  nlohmann::json metadata = nlohmann::json::object();
  // The file stores the weights as float16 (rounded to 11 significant bits: half the file). The
  // network trains in float32 either way; the file, and so every use of it, holds the rounded weights.
  bool weights_float16 = false;

  // Writes the model file; `optimizer` (may be null) is stored too, for resuming training.
  void save(const std::string& path, const nlohmann::json& extra_metadata, torch::optim::Optimizer* optimizer) const;
  // Positions predicted from the network's velocities (double precision).
  std::vector<std::vector<Vector3d>> positions_from(const detail::MotionBatch& batch,
                                                    const torch::Tensor& velocity) const;
  // The Eigen forward pass (motion_inference.hpp) that forecast() runs, made from the network's current
  // weights: built on first use and again whenever a weight has changed since (training, loading),
  // which LibTorch's per-tensor version counters tell.
  std::shared_ptr<const MotionInference> inference() const;

 private:
  mutable std::mutex inference_mutex_;
  mutable std::shared_ptr<const MotionInference> inference_;
  mutable std::int64_t inference_weights_version_ = -1;
};

// Reads the optimizer state stored by Impl::save into `optimizer`; false when the file has none.
bool load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer);

}  // namespace stgf
