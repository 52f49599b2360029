// SPDX-License-Identifier: Apache-2.0
#pragma once
// Φ's forward pass for inference, in Eigen: the same network as motion_network.hpp (LibTorch, used
// for training), computed directly, without LibTorch's per-operator dispatch — at the filter's sizes
// (a few objects per call) that dispatch, not arithmetic, was most of Φ's cost. The math, with
// W x meaning a matrix-vector product and σ the logistic function:
//
//   embed      e_k = ReLU(W_e x_k + b_e)                          x_k: interval k's 7 inputs
//   LSTM       (i, f, g, o) = (σ, σ, tanh, σ)(W_i e_k + W_h h + b)     (PyTorch's gate order)
//              c ← f ⊙ c + i ⊙ g,   h ← o ⊙ tanh(c)             over k = 1…H from h = c = 0:  m = h
//   attention  per layer, over the edges j → i of the object's graph (motion_features.hpp):
//              w_j = W h_j,  message_ji = w_j + U (p_j − p_i)/s_p + b_U
//              score_ji = LeakyReLU_0.2(a_selfᵀ w_i + a_msgᵀ message_ji), clamped to ±30
//              h'_i = ELU(Σ_j softmax_j(score_ji) message_ji)    two layers: m → s
//   decoder    one LSTM cell on m ‖ s ‖ v_last from the encoder's (h, c);   â = W_o h + b_o
//
// Each object is computed on its own, in a fixed order of operations: an object's output depends
// only on its own graph, never on what else is in the call (batch size, other scenes), and is the
// same on any machine for the same build, whatever the thread count or BLAS. It agrees with the
// LibTorch network to float rounding (tested to 1e-5 on random graphs).
//
// An object whose inputs are those of an earlier call takes its encoder state (h, c) from a memo
// (encoding_memo.hpp), compared byte for byte: the result is the same, at a fraction of the cost.

#include <Eigen/Dense>

#include "stgf/model/encoding_memo.hpp"
#include "stgf/model/motion_features.hpp"

namespace stgf {

// The network's weights as LibTorch stores them (out × in matrices), in single precision.
struct MotionNetworkWeights {
  struct Lstm {
    Eigen::MatrixXf input;      // W_i [4 hidden × inputs], gates (i, f, g, o)
    Eigen::MatrixXf recurrent;  // W_h [4 hidden × hidden]
    Eigen::VectorXf bias;       // b = b_ih + b_hh
  };
  struct GraphAttention {
    Eigen::MatrixXf transform;         // W [out × in]
    Eigen::MatrixXf offset_transform;  // U [out × 3]
    Eigen::VectorXf offset_bias;       // b_U [out]
    Eigen::VectorXf score_self;        // a_self [out]
    Eigen::VectorXf score_message;     // a_msg [out]
  };
  Eigen::MatrixXf embed;  // W_e [embedding × 7]
  Eigen::VectorXf embed_bias;
  Lstm encoder;
  GraphAttention attention1;
  GraphAttention attention2;
  Lstm decoder;          // inputs: m (hidden) ‖ s (hidden) ‖ v_last (3)
  Eigen::MatrixXf head;  // W_o [3 × hidden]
  Eigen::VectorXf head_bias;
};

class MotionInference {
 public:
  // Throws std::invalid_argument when the weights' sizes do not fit together.
  explicit MotionInference(MotionNetworkWeights weights);

  // â for every object of `features`, in units of s_v / s_t (as the network's head gives it): [3 × N].
  // Throws std::invalid_argument when the features' history length differs from the network's inputs
  // or an edge is out of order.
  Eigen::Matrix3Xf accelerations(const MotionFeatures& features) const;

 private:
  MotionNetworkWeights weights_;
  Eigen::Index hidden_ = 0;
  mutable EncodingMemo memo_;
};

// The memo's entries: a few hundred scenes' objects, 2 MB at the default sizes.
inline constexpr std::size_t kEncodingMemoSlots = 4096;

}  // namespace stgf
