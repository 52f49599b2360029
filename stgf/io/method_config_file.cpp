// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/method_config_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "stgf/io/input_bounds.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

// YAML marks count lines from 0.
int line_of(const YAML::Node& node) { return node.Mark().line + 1; }

// The keys of one mapping, each a plain name given once (yaml-cpp keeps both entries of a duplicate).
class KeysOfOneMapping {
 public:
  explicit KeysOfOneMapping(std::string path) : path_(std::move(path)) {}
  std::string operator()(const YAML::Node& key) {
    if (!key.IsScalar()) throw InputError(path_, line_of(key), "a setting's name must be a plain word");
    const std::string name = key.as<std::string>();
    const auto [found, inserted] = first_line_.emplace(name, line_of(key));
    if (!inserted) {
      throw InputError(path_, line_of(key), "duplicate key " + quoted_excerpt(name) + " (first at line " + std::to_string(found->second) + ")");
    }
    return name;
  }

 private:
  std::string path_;
  std::map<std::string, int> first_line_;
};

double positive_number(const std::string& path, const std::string& key, const YAML::Node& node) {
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(path, line_of(node), key + " must be a number");
  }
  if (!std::isfinite(value) || value <= 0.0) {
    throw InputError(path, line_of(node), key + " must be a finite number > 0");
  }
  return value;
}

bool boolean(const std::string& path, const std::string& key, const YAML::Node& node) {
  try {
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    throw InputError(path, line_of(node), key + " must be true or false");
  }
}

// The gate's keys (measurement_gate.hpp), in any method's section: true when `key` was one.
bool read_gate_key(const std::string& path, const std::string& key, const std::string& name, const YAML::Node& value,
                   GateOptions& gate) {
  if (key == "gate") {
    gate.enabled = boolean(path, name, value);
  } else if (key == "gate_probability") {
    gate.probability = positive_number(path, name, value);
    if (gate.probability >= 1.0) throw InputError(path, line_of(value), name + " must be below 1 (e.g. 0.999)");
  } else {
    return false;
  }
  return true;
}

void read_wls(const std::string& path, const YAML::Node& node, GateOptions& gate) {
  if (node.IsNull()) return;
  if (!node.IsMap()) throw InputError(path, line_of(node), "wls must be a mapping of settings");
  KeysOfOneMapping keys(path);
  for (const auto& entry : node) {
    const std::string key = keys(entry.first);
    const std::string name = "wls." + key;
    if (!read_gate_key(path, key, name, entry.second, gate)) {
      throw InputError(path, line_of(entry.first), "unknown setting " + quoted_excerpt(name));
    }
  }
}

void read_mmt(const std::string& path, const YAML::Node& node, ConstantVelocityModel& model, GateOptions& gate) {
  if (node.IsNull()) return;  // a section whose keys are all commented out
  if (!node.IsMap()) throw InputError(path, line_of(node), "mmt must be a mapping of settings");
  KeysOfOneMapping keys(path);
  for (const auto& entry : node) {
    const std::string key = keys(entry.first);
    const std::string name = "mmt." + key;
    if (key == "initial_position_variance") {
      model.initial_position_variance = positive_number(path, name, entry.second);
    } else if (key == "initial_velocity_variance") {
      model.initial_velocity_variance = positive_number(path, name, entry.second);
    } else if (key == "position_noise_density") {
      model.position_noise_density = positive_number(path, name, entry.second);
    } else if (key == "velocity_noise_density") {
      model.velocity_noise_density = positive_number(path, name, entry.second);
    } else if (read_gate_key(path, key, name, entry.second, gate)) {
    } else {
      throw InputError(path, line_of(entry.first), "unknown setting " + quoted_excerpt(name));
    }
  }
}

double non_negative_number(const std::string& path, const std::string& key, const YAML::Node& node) {
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(path, line_of(node), key + " must be a number");
  }
  if (!std::isfinite(value) || value < 0.0) throw InputError(path, line_of(node), key + " must be a finite number >= 0");
  return value;
}

// One number >= 0 for all three components, or a list of three (`axes` names them in the message).
Vector3d one_or_three_non_negative(const std::string& path, const std::string& key, const YAML::Node& node,
                                   const std::string& axes) {
  if (!node.IsSequence()) return Vector3d::Constant(non_negative_number(path, key, node));
  if (node.size() != 3) throw InputError(path, line_of(node), key + " must be one number or a list of three (" + axes + ")");
  return {non_negative_number(path, key, node[0]), non_negative_number(path, key, node[1]),
          non_negative_number(path, key, node[2])};
}

// One of `choices` (a YAML string).
std::string one_of(const std::string& path, const std::string& key, const YAML::Node& node,
                   const std::vector<std::string>& choices) {
  const std::string value = node.IsScalar() ? node.as<std::string>() : std::string();
  if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
    std::string listed = choices.back();  // "a, b or c"
    for (std::size_t k = choices.size() - 1; k-- > 0;) listed = choices[k] + (k + 2 == choices.size() ? " or " : ", ") + listed;
    throw InputError(path, line_of(node), key + " must be " + listed);
  }
  return value;
}

void read_ours(const std::string& path, const YAML::Node& node, OursSettings& settings) {
  if (node.IsNull()) return;  // a section whose keys are all commented out
  if (!node.IsMap()) throw InputError(path, line_of(node), "ours must be a mapping of settings");
  KeysOfOneMapping keys(path);
  for (const auto& entry : node) {
    const std::string key = keys(entry.first);
    const std::string name = "ours." + key;
    if (key == "registration") {
      settings.registration = boolean(path, name, entry.second);
    } else if (key == "registration_translation_sigma_m") {
      settings.translation_sigma = one_or_three_non_negative(path, name, entry.second, "x, y, z");
    } else if (key == "adapt_process_noise") {
      settings.adapt_process_noise = boolean(path, name, entry.second);
    } else if (key == "motion_fallback") {
      const std::string value = one_of(path, name, entry.second, {"auto", "off", "always"});
      settings.motion_fallback = value == "auto" ? MotionFallback::kAuto
                                 : value == "off" ? MotionFallback::kOff
                                                  : MotionFallback::kAlways;
    } else if (key == "adapt_registration_prior") {
      settings.adapt_registration_prior = boolean(path, name, entry.second);
    } else if (key == "cross_view_weights") {
      settings.cross_view_weights = boolean(path, name, entry.second);
    } else if (key == "history_velocity_error") {
      settings.history_velocity_error = boolean(path, name, entry.second);
    } else if (key == "registration_noise_ratio") {
      settings.noise_ratio = one_or_three_non_negative(path, name, entry.second, "along, across, vertical");
    } else if (key == "registration_prior_scale") {
      const std::string where =
          one_of(path, name, entry.second, {"auto", "per-scene", "across-scenes", "shrink-across-scenes"});
      settings.registration_scale_learning =
          where == "auto"            ? std::nullopt
          : where == "per-scene"     ? std::optional(RegistrationScaleLearning::kPerScene)
          : where == "across-scenes" ? std::optional(RegistrationScaleLearning::kAcrossScenes)
                                     : std::optional(RegistrationScaleLearning::kShrinkAcrossScenes);
    } else if (key == "process_noise_scale") {
      const std::string where =
          one_of(path, name, entry.second, {"auto", "per-scene", "across-scenes", "grow-across-scenes"});
      settings.process_noise_scale_learning =
          where == "auto"            ? std::nullopt
          : where == "per-scene"     ? std::optional(ProcessNoiseScaleLearning::kPerScene)
          : where == "across-scenes" ? std::optional(ProcessNoiseScaleLearning::kAcrossScenes)
                                     : std::optional(ProcessNoiseScaleLearning::kGrowAcrossScenes);
    } else if (key == "registration_range_scale_sigma") {
      settings.range_scale_sigma = non_negative_number(path, name, entry.second);
    } else if (key == "tracks") {
      settings.per_view_tracks = one_of(path, name, entry.second, {"per-object", "per-view"}) == "per-view";
    } else if (key == "lag_window_s") {
      settings.lag_window = non_negative_number(path, name, entry.second);
    } else if (key == "late_measurements") {
      settings.stop_on_late = one_of(path, name, entry.second, {"leave-out", "stop"}) == "stop";
    } else if (read_gate_key(path, key, name, entry.second, settings.gate)) {
    } else {
      throw InputError(path, line_of(entry.first), "unknown setting " + quoted_excerpt(name));
    }
  }
}

}  // namespace

MethodConfig parse_method_config(const std::string& path, const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& error) {
    throw InputError(path, error.mark.line + 1, "not valid YAML: " + error.msg);
  }
  MethodConfig config;
  if (root.IsNull()) return config;
  if (!root.IsMap()) throw InputError(path, line_of(root), "expected a mapping of method names to settings");
  KeysOfOneMapping sections(path);
  try {
    for (const auto& entry : root) {
      const std::string method = sections(entry.first);
      if (method == "mmt") {
        read_mmt(path, entry.second, config.mmt, config.mmt_gate);
      } else if (method == "wls") {
        read_wls(path, entry.second, config.wls_gate);
      } else if (method == "ours") {
        read_ours(path, entry.second, config.ours);
      } else {
        throw InputError(path, line_of(entry.first), "unknown section " + quoted_excerpt(method) + " (known: wls, mmt, ours)");
      }
    }
  } catch (const YAML::Exception& error) {
    // Anything yaml-cpp finds beyond the checks above, still at its file and line.
    throw InputError(path, error.mark.line + 1, error.msg);
  }
  return config;
}

MethodConfig read_method_config(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, 0, "is a directory, not a YAML file");
  std::ifstream file(path);
  if (!file) throw InputError(path, 0, "cannot open the file");
  std::ostringstream text;
  text << file.rdbuf();
  return parse_method_config(path, text.str());
}

}  // namespace stgf
