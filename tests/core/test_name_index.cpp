// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/name_index.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace stgf {
namespace {

TEST(NameIndex, GivesOneIdPerNameWhateverTheOrderOfLookUps) {
  NameIndex index;
  const std::uint32_t a = index.id("cam-a");
  const std::uint32_t b = index.id("cam-b");
  EXPECT_NE(a, b);
  // Repeats, the name after the last, the first name, and a name looked up by hash.
  for (const char* name : {"cam-b", "cam-a", "cam-b", "cam-c", "cam-a", "cam-c", "cam-c", "cam-b"}) {
    const std::uint32_t id = index.id(name);
    EXPECT_EQ(index.id(std::string(name)), id);
  }
  EXPECT_EQ(index.id("cam-a"), a);
  EXPECT_EQ(index.id("cam-b"), b);
  EXPECT_NE(index.id("cam-c"), a);
  EXPECT_NE(index.id("cam-c"), b);
}

TEST(NameIndex, RanksTheDistinctNamesOfACallInNameOrder) {
  NameIndex index;
  std::vector<std::uint32_t> ids;
  for (const char* name : {"o10", "o2", "o10", "o1", "o2"}) ids.push_back(index.id(name));
  index.rank(ids);
  EXPECT_EQ(index.rank_of(index.id("o1")), 0u);
  EXPECT_EQ(index.rank_of(index.id("o10")), 1u);  // byte order, as std::string compares
  EXPECT_EQ(index.rank_of(index.id("o2")), 2u);
  // A later call ranks only its own names.
  const std::vector<std::uint32_t> later{index.id("o2"), index.id("o0")};
  index.rank(later);
  EXPECT_EQ(index.rank_of(index.id("o0")), 0u);
  EXPECT_EQ(index.rank_of(index.id("o2")), 1u);
}

TEST(NameIndex, ForgetsItsNamesOnlyPastTheLimit) {
  NameIndex index;
  for (std::size_t k = 0; k <= NameIndex::kMaxNames; ++k) index.id("o" + std::to_string(k));
  const std::uint32_t before = index.id("o5");
  index.trim();  // more than kMaxNames: numbered anew
  EXPECT_EQ(index.id("new"), 0u);
  EXPECT_NE(index.id("o5"), before);
}

TEST(NameIndex, SameNameComparesWholeNames) {
  EXPECT_TRUE(same_name("view-1", "view-1"));
  EXPECT_FALSE(same_name("view-1", "view-2"));
  EXPECT_FALSE(same_name("view", "view-1"));
  EXPECT_TRUE(same_name("", ""));
}

}  // namespace
}  // namespace stgf
