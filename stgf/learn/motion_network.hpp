// SPDX-License-Identifier: Apache-2.0
#pragma once
// The network of Φ in LibTorch (see motion_model.hpp for the math). Private to the learn layer:
// only motion_model.cpp and motion_training.cpp include it, so LibTorch stays out of public headers.

#include <torch/torch.h>

#include <span>
#include <vector>

#include "stgf/learn/motion_model.hpp"

namespace stgf::detail {

// A batch of graphs as tensors (float32). Positions never enter the network as absolute values:
// only differences, computed in double before conversion, so world coordinates of any size work.
struct MotionBatch {
  torch::Tensor motion;           // [N, H, 7]: v_k / s_v (3), a_k s_t / s_v (3), valid
  torch::Tensor last_velocity;    // [N, 3]: v_last / s_v (zero without a velocity)
  torch::Tensor horizon;          // [N, 1]: Δt / s_t
  torch::Tensor last_interval;    // [N, 1]: Δt_last / s_t (zero without a velocity)
  torch::Tensor edge_source;      // [E] int64: neighbour j
  torch::Tensor edge_target;      // [E] int64: object i that attends to j
  torch::Tensor edge_offset;      // [E, 3]: (p_j − p_i) / s_p
  // Per object, in double, to turn the predicted velocity into a position.
  std::vector<Vector3d> last_positions;
  std::vector<double> horizons;   // Δt (s)
  std::vector<Vector3d> last_velocities;  // v_last (m/s), zero without a velocity
  std::vector<double> last_intervals;     // Δt_last (s), zero without a velocity
  std::vector<std::size_t> graph_offsets;  // first object of each graph; size = graphs + 1
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
  nlohmann::json metadata = nlohmann::json::object();

  // Writes the model file; `optimizer` (may be null) is stored too, for resuming training.
  void save(const std::string& path, const nlohmann::json& extra_metadata, torch::optim::Optimizer* optimizer) const;
  // Positions predicted from the network's velocities (double precision).
  std::vector<std::vector<Vector3d>> positions_from(const detail::MotionBatch& batch,
                                                    const torch::Tensor& velocity) const;
  // Forecasts from the network's accelerations (double precision).
  std::vector<std::vector<MotionForecast>> forecasts_from(const detail::MotionBatch& batch,
                                                         const torch::Tensor& acceleration) const;
};

// Reads the optimizer state stored by Impl::save into `optimizer`; false when the file has none.
bool load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer);

}  // namespace stgf
