// SPDX-License-Identifier: Apache-2.0
#pragma once
// The estimates file (DESIGN §3):
//   scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method
// One row per (scene, t, view, object) estimate; the method column names what produced it.

#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct EstimateFile {
  std::string path;
  std::vector<Estimate> rows;
  std::vector<std::string> methods;  // method of each row
  std::vector<int> lines;
};

EstimateFile read_estimates(const std::string& path);
EstimateFile parse_estimates(const std::string& path, std::string_view text);
void write_estimates(const std::string& path, std::span<const Estimate> rows, const std::string& method);

}  // namespace stgf
