// SPDX-License-Identifier: Apache-2.0
#pragma once
// Φ's encoder state (h, c) of an object is a function of that object's motion inputs alone
// (motion_inference.hpp: H intervals × 7 numbers). On unsynchronised clocks a scene asks Φ for
// forecasts whenever one of its tracks gains a history position — several times per frame period —
// and every other object of the scene comes again with the inputs it had the time before. The memo
// keeps the latest encodings by their inputs, so that each history is encoded about once.
//
// A look-up compares the inputs in full, byte for byte: an encoding read from the memo is the one
// computing it gives, so forecasts depend neither on what the memo holds nor on the order of calls
// or threads. Direct-mapped: each input is hashed to one of `slots` entries, and a later input with
// the same slot replaces it (a miss then costs one encoding). Memory: slots × (inputs + 2 · hidden)
// floats, taken at the first store (which sets the inputs' size; a store of another size starts the
// memo afresh). Thread-safe: a lock around each look-up and each store.

#include <cstddef>
#include <mutex>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace stgf {

class EncodingMemo {
 public:
  // `hidden`: the size of h and of c.
  EncodingMemo(std::size_t slots, Eigen::Index hidden);
  // A copy is an empty memo of the same shape (what is remembered stays with its model).
  EncodingMemo(const EncodingMemo& other);
  EncodingMemo& operator=(const EncodingMemo& other);

  // The encoding stored for exactly these inputs, if any: h and c (each `hidden` long) are written.
  bool find(std::span<const float> inputs, Eigen::VectorXf& h, Eigen::VectorXf& c) const;
  void store(std::span<const float> inputs, const Eigen::VectorXf& h, const Eigen::VectorXf& c);

 private:
  std::size_t slot_of(std::span<const float> inputs) const;
  std::size_t stride() const { return inputs_ + 2 * static_cast<std::size_t>(hidden_); }
  float* entry(std::size_t slot) { return table_.data() + slot * stride(); }
  const float* entry(std::size_t slot) const { return table_.data() + slot * stride(); }

  std::size_t slots_;
  Eigen::Index hidden_;
  std::size_t inputs_ = 0;  // per entry: the inputs, then h, then c
  mutable std::mutex mutex_;
  std::vector<float> table_;     // empty until the first store
  std::vector<char> occupied_;   // per slot
};

}  // namespace stgf
