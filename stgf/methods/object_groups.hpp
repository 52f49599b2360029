// SPDX-License-Identifier: Apache-2.0
#pragma once
// Groups one step's measurements by object, for methods that keep one estimate per object and
// give it to every view that saw the object.

#include <span>
#include <string_view>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct ObjectGroup {
  std::string_view object;
  std::vector<Gaussian3> measurements;  // the views' N(z_u, R_u), in step order
  std::vector<std::string_view> views;  // the view of each
};

// One estimate per measurement row: `estimate_object(group)` is called once per object (objects in
// order of first appearance) and its result is given to each of that object's rows.
template <class EstimateObject>
std::vector<Gaussian3> estimate_per_object(std::span<const Measurement* const> measurements,
                                           EstimateObject&& estimate_object);

// --- implementation ---

struct ObjectGrouping {
  std::vector<ObjectGroup> groups;
  std::vector<std::size_t> group_of_row;
};
ObjectGrouping group_by_object(std::span<const Measurement* const> measurements);

template <class EstimateObject>
std::vector<Gaussian3> estimate_per_object(std::span<const Measurement* const> measurements,
                                           EstimateObject&& estimate_object) {
  const ObjectGrouping grouping = group_by_object(measurements);
  std::vector<Gaussian3> per_group;
  per_group.reserve(grouping.groups.size());
  for (const ObjectGroup& group : grouping.groups) per_group.push_back(estimate_object(group));
  std::vector<Gaussian3> per_row;
  per_row.reserve(measurements.size());
  for (std::size_t group : grouping.group_of_row) per_row.push_back(per_group[group]);
  return per_row;
}

}  // namespace stgf
