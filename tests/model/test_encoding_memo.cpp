// SPDX-License-Identifier: Apache-2.0
// Φ's memo of encoder states (model/encoding_memo.hpp): an entry is found only for exactly its
// inputs, a later input of the same slot replaces it, a copy starts empty, inputs of another size
// start the memo afresh; and with Φ itself, an object found in the memo gets the same bits as one
// encoded (tests/learn/test_motion_inference.cpp compares whole batches).

#include "stgf/model/encoding_memo.hpp"

#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace stgf {
namespace {

TEST(EncodingMemo, FindsExactlyTheInputsStored) {
  EncodingMemo memo(64, 4);
  const std::vector<float> inputs = {0.5f, -1.0f, 2.0f, 0.0f, 3.25f, 1e-7f};
  Eigen::VectorXf h(4), c(4);
  EXPECT_FALSE(memo.find(inputs, h, c));  // empty
  const Eigen::VectorXf stored_h = Eigen::VectorXf::LinSpaced(4, 1.0f, 4.0f);
  const Eigen::VectorXf stored_c = Eigen::VectorXf::LinSpaced(4, -4.0f, -1.0f);
  memo.store(inputs, stored_h, stored_c);
  ASSERT_TRUE(memo.find(inputs, h, c));
  EXPECT_EQ(h, stored_h);
  EXPECT_EQ(c, stored_c);
  std::vector<float> other = inputs;
  other.back() = 1.0000001e-7f;  // one bit away
  EXPECT_FALSE(memo.find(other, h, c));
  other = inputs;
  other[3] = -0.0f;  // equal as a number, another input as bytes: never mistaken for it
  EXPECT_FALSE(memo.find(other, h, c));
}

TEST(EncodingMemo, ALaterInputReplacesTheSlot) {
  EncodingMemo memo(1, 2);  // every input maps to the one slot
  const std::vector<float> first = {1.0f, 2.0f}, second = {3.0f, 4.0f};
  Eigen::VectorXf h(2), c(2);
  memo.store(first, Eigen::Vector2f(1.0f, 1.0f), Eigen::Vector2f(2.0f, 2.0f));
  memo.store(second, Eigen::Vector2f(5.0f, 5.0f), Eigen::Vector2f(6.0f, 6.0f));
  EXPECT_FALSE(memo.find(first, h, c));
  ASSERT_TRUE(memo.find(second, h, c));
  EXPECT_EQ(h, Eigen::Vector2f(5.0f, 5.0f));
}

TEST(EncodingMemo, ACopyStartsEmptyAndInputsOfAnotherSizeStartAfresh) {
  EncodingMemo memo(16, 2);
  const std::vector<float> inputs = {1.0f, 2.0f};
  Eigen::VectorXf h(2), c(2);
  memo.store(inputs, Eigen::Vector2f(1.0f, 1.0f), Eigen::Vector2f(2.0f, 2.0f));
  const EncodingMemo copy(memo);
  EXPECT_FALSE(copy.find(inputs, h, c));
  EncodingMemo assigned(4, 2);
  assigned = memo;
  EXPECT_FALSE(assigned.find(inputs, h, c));
  EXPECT_TRUE(memo.find(inputs, h, c));
  const std::vector<float> longer = {1.0f, 2.0f, 3.0f};
  memo.store(longer, Eigen::Vector2f(3.0f, 3.0f), Eigen::Vector2f(4.0f, 4.0f));
  EXPECT_FALSE(memo.find(inputs, h, c));
  EXPECT_TRUE(memo.find(longer, h, c));
}

TEST(EncodingMemo, RejectsStatesOfAnotherSize) {
  EncodingMemo memo(16, 2);
  const std::vector<float> inputs = {1.0f};
  EXPECT_THROW(memo.store(inputs, Eigen::Vector3f::Zero(), Eigen::Vector2f::Zero()), std::invalid_argument);
  EXPECT_THROW(EncodingMemo(0, 2), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
