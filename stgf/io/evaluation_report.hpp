// SPDX-License-Identifier: Apache-2.0
#pragma once
// An Evaluation as a Markdown table (one row per method, then DE by number of views; on request an
// axis's error by stated variance) and as JSON (all of it).

#include <string>

#include <nlohmann/json.hpp>

#include "stgf/io/evaluation.hpp"

namespace stgf {

std::string evaluation_markdown(const Evaluation& evaluation);
// One axis's (0, 1, 2: x, y, z) squared error against the stated variance (MethodScore::by_variance):
// a row per octave of the variance, a column per method with r_a² / P̂_aa and the bin's rows.
std::string error_by_variance_markdown(const Evaluation& evaluation, int axis);
nlohmann::json evaluation_json(const Evaluation& evaluation);

}  // namespace stgf
