// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/encoding_memo.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string_view>

namespace stgf {

EncodingMemo::EncodingMemo(std::size_t slots, Eigen::Index hidden) : slots_(slots), hidden_(hidden) {
  if (slots == 0 || hidden < 0) throw std::invalid_argument("EncodingMemo: needs a slot and a non-negative hidden size");
}

EncodingMemo::EncodingMemo(const EncodingMemo& other) : EncodingMemo(other.slots_, other.hidden_) {}

EncodingMemo& EncodingMemo::operator=(const EncodingMemo& other) {
  if (this == &other) return *this;
  const std::lock_guard lock(mutex_);
  slots_ = other.slots_;
  hidden_ = other.hidden_;
  inputs_ = 0;
  table_.clear();
  occupied_.clear();
  return *this;
}

std::size_t EncodingMemo::slot_of(std::span<const float> inputs) const {
  const std::string_view bytes(reinterpret_cast<const char*>(inputs.data()), inputs.size_bytes());
  return std::hash<std::string_view>{}(bytes) % slots_;
}

bool EncodingMemo::find(std::span<const float> inputs, Eigen::VectorXf& h, Eigen::VectorXf& c) const {
  const std::size_t slot = slot_of(inputs);
  const std::lock_guard lock(mutex_);
  if (inputs.size() != inputs_ || table_.empty() || !occupied_[slot]) return false;
  const float* stored = entry(slot);
  if (std::memcmp(stored, inputs.data(), inputs.size_bytes()) != 0) return false;
  h = Eigen::Map<const Eigen::VectorXf>(stored + inputs_, hidden_);
  c = Eigen::Map<const Eigen::VectorXf>(stored + inputs_ + static_cast<std::size_t>(hidden_), hidden_);
  return true;
}

void EncodingMemo::store(std::span<const float> inputs, const Eigen::VectorXf& h, const Eigen::VectorXf& c) {
  if (h.size() != hidden_ || c.size() != hidden_) throw std::invalid_argument("EncodingMemo::store: h or c of another size");
  const std::size_t slot = slot_of(inputs);
  const std::lock_guard lock(mutex_);
  if (table_.empty() || inputs.size() != inputs_) {
    inputs_ = inputs.size();
    table_.assign(slots_ * stride(), 0.0f);
    occupied_.assign(slots_, 0);
  }
  float* stored = entry(slot);
  std::copy(inputs.begin(), inputs.end(), stored);
  std::copy(h.data(), h.data() + hidden_, stored + inputs_);
  std::copy(c.data(), c.data() + hidden_, stored + inputs_ + static_cast<std::size_t>(hidden_));
  occupied_[slot] = 1;
}

}  // namespace stgf
