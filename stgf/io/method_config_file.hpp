// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reads method settings from a YAML file (see config/methods.yaml for every key, its meaning, unit
// and default). Keys left out keep their defaults; an unknown key, a non-number or a value out of
// range is an InputError with the file and line.

#include <string>

#include "stgf/methods/registry.hpp"

namespace stgf {

MethodConfig read_method_config(const std::string& path);
MethodConfig parse_method_config(const std::string& path, const std::string& text);

}  // namespace stgf
