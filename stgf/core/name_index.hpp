// SPDX-License-Identifier: Apache-2.0
#pragma once
// Names (of objects, of views) as small integer ids, so that the rows of an event are ordered by
// name with a hash look-up per row — none when a row repeats the name of the row before, as rows
// grouped by object or by view do — and O(d log d) string comparisons for the d distinct names to
// rank, instead of O(n log n) string comparisons to sort n rows.
//
// The ids are an accelerator kept across calls so that looking up a name seen before allocates
// nothing; nothing may keep an id past the call that made it, since clear() (once more than
// kMaxNames names are held) numbers them anew. An id says nothing about name order: rank() does.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace stgf {

// a == b for names, without a call into the C library's memcmp, whose start-up costs more than
// comparing the few characters of a typical name (as it is done for every row of every event).
inline bool same_name(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k] != b[k]) return false;
  }
  return true;
}

class NameIndex {
 public:
  static constexpr std::size_t kMaxNames = 1 << 16;

  NameIndex() = default;
  // The ids point into the map's own strings, so a copy would point into the original's.
  NameIndex(const NameIndex&) = delete;
  NameIndex& operator=(const NameIndex&) = delete;
  NameIndex(NameIndex&&) = default;
  NameIndex& operator=(NameIndex&&) = default;

  // Forgets every name when more than kMaxNames are held (bounds memory over a long stream).
  void trim() {
    if (names_.size() > kMaxNames) clear();
  }
  void clear();

  // The id of `name`, added if new.
  std::uint32_t id(std::string_view name);

  // Ranks the distinct ids among `ids` in name order: afterwards rank_of(id) is the rank of id's name
  // among them (0 for the first).
  void rank(std::span<const std::uint32_t> ids);
  std::uint32_t rank_of(std::uint32_t id) const { return ranks_[id]; }

 private:
  struct Hash {
    using is_transparent = void;
    std::size_t operator()(std::string_view name) const { return std::hash<std::string_view>{}(name); }
  };
  std::unordered_map<std::string, std::uint32_t, Hash, std::equal_to<>> ids_;
  std::vector<std::string_view> names_;  // by id (into ids_' keys, which do not move)
  std::vector<std::uint32_t> ranks_;     // by id, as of the last rank()
  std::vector<std::uint64_t> marks_;     // by id: the rank() call that last saw it
  std::vector<std::uint32_t> distinct_;  // rank()'s work space
  std::uint64_t generation_ = 0;
  std::uint32_t last_ = 0;  // the id looked up last
};

}  // namespace stgf
