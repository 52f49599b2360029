// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/name_index.hpp"

#include <algorithm>

namespace stgf {

void NameIndex::clear() {
  ids_.clear();
  names_.clear();
  ranks_.clear();
  marks_.clear();
  last_ = 0;
}

std::uint32_t NameIndex::id(std::string_view name) {
  // Rows grouped by one name cycle through the other in the same order every time (the views of each
  // object, or the objects of each view): the name after the last one is the likeliest next.
  if (!names_.empty()) {
    if (same_name(name, names_[last_])) return last_;
    if (last_ + 1 < names_.size() && same_name(name, names_[last_ + 1])) return ++last_;
    if (same_name(name, names_.front())) return last_ = 0;
  }
  auto found = ids_.find(name);
  if (found == ids_.end()) {
    found = ids_.emplace(std::string(name), static_cast<std::uint32_t>(names_.size())).first;
    names_.push_back(found->first);
    ranks_.push_back(0);
    marks_.push_back(0);
  }
  last_ = found->second;
  return last_;
}

void NameIndex::rank(std::span<const std::uint32_t> ids) {
  ++generation_;
  distinct_.clear();
  for (const std::uint32_t id : ids) {
    if (marks_[id] == generation_) continue;
    marks_[id] = generation_;
    distinct_.push_back(id);
  }
  std::sort(distinct_.begin(), distinct_.end(), [this](std::uint32_t a, std::uint32_t b) { return names_[a] < names_[b]; });
  for (std::size_t r = 0; r < distinct_.size(); ++r) ranks_[distinct_[r]] = static_cast<std::uint32_t>(r);
}

}  // namespace stgf
