#pragma once
// Methods by name, as the CLI's `--method` knows them.

#include <memory>
#include <string>
#include <vector>

#include "stgf/core/constant_velocity_filter.hpp"
#include "stgf/methods/localizer.hpp"

namespace stgf {

// Settings of every method, read from the YAML config (see config/methods.yaml).
struct MethodConfig {
  ConstantVelocityModel mmt;
};

// The names `make_localizer` accepts, in the order tables list them.
const std::vector<std::string>& method_names();

// A fresh localizer for one scene. Throws std::invalid_argument for an unknown name.
std::unique_ptr<Localizer> make_localizer(const std::string& name, const MethodConfig& config);

}  // namespace stgf
