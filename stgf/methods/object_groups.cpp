// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/object_groups.hpp"

#include <unordered_map>

namespace stgf {

ObjectGrouping group_by_object(std::span<const Measurement* const> measurements) {
  ObjectGrouping grouping;
  grouping.group_of_row.reserve(measurements.size());
  std::unordered_map<std::string_view, std::size_t> group_of_object;
  for (const Measurement* measurement : measurements) {
    const auto [it, inserted] =
        group_of_object.try_emplace(measurement->object, grouping.groups.size());
    if (inserted) grouping.groups.push_back(ObjectGroup{measurement->object, {}, {}});
    grouping.groups[it->second].measurements.push_back(measurement->position);
    grouping.groups[it->second].views.push_back(measurement->view);
    grouping.group_of_row.push_back(it->second);
  }
  return grouping;
}

}  // namespace stgf
