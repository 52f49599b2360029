// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/motion_inference.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace stgf {
namespace {

void require(bool condition, const std::string& what) {
  if (!condition) throw std::invalid_argument("motion network weights: " + what);
}

void check_lstm(const MotionNetworkWeights::Lstm& lstm, Eigen::Index inputs, Eigen::Index hidden, const char* name) {
  require(lstm.input.rows() == 4 * hidden && lstm.input.cols() == inputs, std::string(name) + " input weights");
  require(lstm.recurrent.rows() == 4 * hidden && lstm.recurrent.cols() == hidden,
          std::string(name) + " recurrent weights");
  require(lstm.bias.size() == 4 * hidden, std::string(name) + " bias");
}

void check_attention(const MotionNetworkWeights::GraphAttention& layer, Eigen::Index inputs, Eigen::Index outputs,
                     const char* name) {
  require(layer.transform.rows() == outputs && layer.transform.cols() == inputs, std::string(name) + " W");
  require(layer.offset_transform.rows() == outputs && layer.offset_transform.cols() == 3, std::string(name) + " U");
  require(layer.offset_bias.size() == outputs && layer.score_self.size() == outputs &&
              layer.score_message.size() == outputs,
          std::string(name) + " bias or scores");
}

// One LSTM step from its gate pre-activations (i, f, g, o): c ← f ⊙ c + i ⊙ g, h ← o ⊙ tanh(c).
void lstm_step(const Eigen::VectorXf& gates, Eigen::Index hidden, Eigen::VectorXf& h, Eigen::VectorXf& c) {
  const auto input_gate = gates.segment(0, hidden).array().logistic();
  const auto forget_gate = gates.segment(hidden, hidden).array().logistic();
  const auto candidate = gates.segment(2 * hidden, hidden).array().tanh();
  const auto output_gate = gates.segment(3 * hidden, hidden).array().logistic();
  c.array() = forget_gate * c.array() + input_gate * candidate;
  h.array() = output_gate * c.array().tanh();
}

// One graph-attention layer over the objects [first, last) of one graph, whose edges are
// [edge_first, edge_last) grouped by target: in (columns = objects) → out.
void attend(const MotionNetworkWeights::GraphAttention& layer, const MotionFeatures& features, std::size_t first,
            std::size_t last, std::size_t edge_first, std::size_t edge_last, const Eigen::MatrixXf& in,
            Eigen::MatrixXf& out, Eigen::MatrixXf& transformed, Eigen::VectorXf& message, Eigen::VectorXf& total) {
  for (std::size_t n = first; n < last; ++n) {
    const auto column = static_cast<Eigen::Index>(n);
    transformed.col(column).noalias() = layer.transform * in.col(column);  // w_n = W h_n
  }
  std::size_t e = edge_first;
  for (std::size_t i = first; i < last; ++i) {
    const auto target = static_cast<Eigen::Index>(i);
    const float self_score = layer.score_self.dot(transformed.col(target));
    // Softmax over the edges into i, accumulated as Σ w_e message_e / Σ w_e.
    total.setZero();
    float weight_sum = 0.0f;
    for (; e < edge_last && static_cast<std::size_t>(features.edge_target[e]) == i; ++e) {
      const auto source = static_cast<Eigen::Index>(features.edge_source[e]);
      const Eigen::Map<const Eigen::Vector3f> offset(&features.edge_offset[3 * e]);
      message.noalias() = transformed.col(source) + layer.offset_bias;
      message.noalias() += layer.offset_transform * offset;
      float score = self_score + layer.score_message.dot(message);
      if (score < 0.0f) score *= 0.2f;                 // LeakyReLU(0.2)
      score = std::clamp(score, -30.0f, 30.0f);        // as in training: exp cannot overflow
      const float weight = std::exp(score);
      weight_sum += weight;
      total += weight * message;
    }
    require(weight_sum > 0.0f, "an object has no edge into it (not even its self-loop)");
    out.col(target) = (total / weight_sum).unaryExpr([](float x) { return x > 0.0f ? x : std::expm1(x); });  // ELU
  }
  require(e == edge_last, "the edges are not grouped by target");
}

}  // namespace

MotionInference::MotionInference(MotionNetworkWeights weights)
    : weights_(std::move(weights)), hidden_(weights_.encoder.recurrent.cols()), memo_(kEncodingMemoSlots, hidden_) {
  const MotionNetworkWeights& w = weights_;
  const Eigen::Index embedding = w.embed.rows();
  require(w.embed.cols() == kMotionFeatures && w.embed_bias.size() == embedding, "embedding");
  check_lstm(w.encoder, embedding, hidden_, "encoder");
  const Eigen::Index attention_hidden = w.attention1.transform.rows();
  check_attention(w.attention1, hidden_, attention_hidden, "attention1");
  check_attention(w.attention2, attention_hidden, hidden_, "attention2");
  check_lstm(w.decoder, 2 * hidden_ + 3, hidden_, "decoder");
  require(w.head.rows() == 3 && w.head.cols() == hidden_ && w.head_bias.size() == 3, "head");
}

Eigen::Matrix3Xf MotionInference::accelerations(const MotionFeatures& features) const {
  const MotionNetworkWeights& w = weights_;
  const auto objects = static_cast<Eigen::Index>(features.objects());
  const int history = features.history;
  if (features.motion.size() != static_cast<std::size_t>(objects) * history * kMotionFeatures) {
    throw std::invalid_argument("motion features: the history length does not match the motion inputs");
  }
  const Eigen::Index hidden = hidden_;

  // Encoder: m (and the cell state c) per object.
  Eigen::MatrixXf motion_embedding(hidden, objects), cell(hidden, objects);
  Eigen::VectorXf embedded(w.embed.rows()), gates(4 * hidden), h(hidden), c(hidden);
  const std::size_t inputs = static_cast<std::size_t>(history) * kMotionFeatures;
  for (Eigen::Index n = 0; n < objects; ++n) {
    const std::span<const float> object_inputs(features.motion.data() + static_cast<std::size_t>(n) * inputs, inputs);
    if (memo_.find(object_inputs, h, c)) {
      motion_embedding.col(n) = h;
      cell.col(n) = c;
      continue;
    }
    h.setZero();
    c.setZero();
    for (int k = 0; k < history; ++k) {
      const Eigen::Map<const Eigen::Matrix<float, kMotionFeatures, 1>> x(
          &features.motion[(static_cast<std::size_t>(n) * history + k) * kMotionFeatures]);
      embedded.noalias() = w.embed * x;
      embedded = (embedded + w.embed_bias).cwiseMax(0.0f);
      gates = w.encoder.bias;
      gates.noalias() += w.encoder.input * embedded;
      gates.noalias() += w.encoder.recurrent * h;
      lstm_step(gates, hidden, h, c);
    }
    memo_.store(object_inputs, h, c);
    motion_embedding.col(n) = h;
    cell.col(n) = c;
  }

  // Spatial: two attention layers within each graph.
  const Eigen::Index attention_hidden = w.attention1.transform.rows();
  Eigen::MatrixXf first_layer(attention_hidden, objects), spatial(hidden, objects);
  Eigen::MatrixXf transformed1(attention_hidden, objects), transformed2(hidden, objects);
  Eigen::VectorXf message1(attention_hidden), total1(attention_hidden), message2(hidden), total2(hidden);
  std::size_t edge_first = 0;
  for (std::size_t g = 0; g + 1 < features.graph_offsets.size(); ++g) {
    const std::size_t first = features.graph_offsets[g];
    const std::size_t last = features.graph_offsets[g + 1];
    std::size_t edge_last = edge_first;
    while (edge_last < features.edges() && static_cast<std::size_t>(features.edge_target[edge_last]) < last) {
      ++edge_last;
    }
    attend(w.attention1, features, first, last, edge_first, edge_last, motion_embedding, first_layer, transformed1,
           message1, total1);
    attend(w.attention2, features, first, last, edge_first, edge_last, first_layer, spatial, transformed2, message2,
           total2);
    edge_first = edge_last;
  }

  // Decoder: one LSTM cell on m ‖ s ‖ v_last from the encoder's state, then the head.
  Eigen::Matrix3Xf acceleration(3, objects);
  Eigen::VectorXf input(2 * hidden + 3);
  for (Eigen::Index n = 0; n < objects; ++n) {
    input.head(hidden) = motion_embedding.col(n);
    input.segment(hidden, hidden) = spatial.col(n);
    input.tail(3) = Eigen::Map<const Eigen::Vector3f>(&features.last_velocity[3 * static_cast<std::size_t>(n)]);
    h = motion_embedding.col(n);
    c = cell.col(n);
    gates = w.decoder.bias;
    gates.noalias() += w.decoder.input * input;
    gates.noalias() += w.decoder.recurrent * h;
    lstm_step(gates, hidden, h, c);
    acceleration.col(n) = w.head_bias;
    acceleration.col(n).noalias() += w.head * h;
  }
  return acceleration;
}

}  // namespace stgf
