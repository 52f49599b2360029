// SPDX-License-Identifier: Apache-2.0
#pragma once
// An Evaluation as a Markdown table (one row per method, then DE by number of views) and as JSON.

#include <string>

#include <nlohmann/json.hpp>

#include "stgf/io/evaluation.hpp"

namespace stgf {

std::string evaluation_markdown(const Evaluation& evaluation);
nlohmann::json evaluation_json(const Evaluation& evaluation);

}  // namespace stgf
