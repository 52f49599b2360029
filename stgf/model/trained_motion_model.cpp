// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/trained_motion_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "stgf/io/input_error.hpp"
#include "stgf/model/motion_features.hpp"
#include "stgf/model/torch_archive.hpp"

namespace stgf {
namespace {

nlohmann::json matrix_json(const Matrix3d& m) {
  return {{m(0, 0), m(0, 1), m(0, 2)}, {m(1, 0), m(1, 1), m(1, 2)}, {m(2, 0), m(2, 1), m(2, 2)}};
}

Matrix3d matrix_from(const nlohmann::json& j) {
  Matrix3d m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = j.at(r).at(c).get<double>();
  }
  return m;
}

// FNV-1a, 64 bit. It catches corruption (a flipped byte anywhere in what it covers), not tampering.
class Checksum {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t k = 0; k < size; ++k) hash_ = (hash_ ^ bytes[k]) * 0x100000001b3ULL;
  }
  void add(const std::string& text) { add(text.data(), text.size()); }
  std::string hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// A weight as an Eigen matrix (LibTorch stores out × in, row-major) or vector.
Eigen::MatrixXf matrix_of(const std::vector<float>& values, std::int64_t rows, std::int64_t columns) {
  return Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(values.data(), rows,
                                                                                                 columns);
}

Eigen::VectorXf vector_of(const std::vector<float>& values) {
  return Eigen::Map<const Eigen::VectorXf>(values.data(), static_cast<Eigen::Index>(values.size()));
}

// Q_ref and Δt_ref, and the longer intervals' Q only when there are any (a model without them writes
// the same config, and so the same file, as before they existed).
nlohmann::json process_noise_json(const MotionModelSettings& settings) {
  nlohmann::json json{{"reference", matrix_json(settings.process_noise_reference)}, {"period", settings.process_noise_period}};
  const auto nodes_json = [](const std::vector<IntervalNoise>& nodes) {
    nlohmann::json list = nlohmann::json::array();
    for (const IntervalNoise& node : nodes) list.push_back({{"interval", node.interval}, {"covariance", matrix_json(node.covariance)}});
    return list;
  };
  if (!settings.process_noise_intervals.empty()) json["intervals"] = nodes_json(settings.process_noise_intervals);
  if (!settings.coasting_process_noise.empty()) json["coasting"] = nodes_json(settings.coasting_process_noise);
  return json;
}

// Nodes of a Q curve from the file: finite, at increasing intervals beyond `after`.
std::vector<IntervalNoise> nodes_from(const nlohmann::json& list, double after) {
  std::vector<IntervalNoise> nodes;
  for (const nlohmann::json& node : list) {
    nodes.push_back({node.at("interval").get<double>(), matrix_from(node.at("covariance"))});
  }
  check_process_noise_nodes(nodes, after);
  return nodes;
}

}  // namespace

nlohmann::json settings_json(const MotionModelSettings& settings) {
  const MotionModelShape& s = settings.shape;
  const MotionNormalisation& n = settings.normalisation;
  nlohmann::json normalisation = {
      {"speed", n.speed}, {"period", n.period}, {"length", n.length}, {"longest_interval", n.longest_interval}};
  // Only where it differs from s_t (several benchmarks): a model of one writes what it wrote before.
  if (n.frame_period_or_period() != n.period) normalisation["frame_period"] = n.frame_period;
  return {{"shape",
           {{"history_length", s.history_length}, {"embedding", s.embedding}, {"hidden", s.hidden},
            {"attention_hidden", s.attention_hidden}, {"max_fully_connected", s.max_fully_connected},
            {"nearest_neighbours", s.nearest_neighbours}}},
          {"normalisation", normalisation},
          {"process_noise", process_noise_json(settings)},
          {"metadata", settings.metadata}};
}

MotionModelSettings settings_from_json(const nlohmann::json& config) {
  MotionModelSettings settings;
  const nlohmann::json& j = config.at("shape");
  MotionModelShape& s = settings.shape;
  s.history_length = j.at("history_length").get<int>();
  s.embedding = j.at("embedding").get<int>();
  s.hidden = j.at("hidden").get<int>();
  s.attention_hidden = j.at("attention_hidden").get<int>();
  s.max_fully_connected = j.at("max_fully_connected").get<int>();
  s.nearest_neighbours = j.at("nearest_neighbours").get<int>();
  if (s.history_length < 1 || s.embedding < 1 || s.hidden < 1 || s.attention_hidden < 1 || s.max_fully_connected < 1 ||
      s.nearest_neighbours < 1) {
    throw std::invalid_argument("shape has a size below 1");
  }
  const nlohmann::json& n = config.at("normalisation");
  settings.normalisation = {n.at("speed").get<double>(), n.at("period").get<double>(), n.at("length").get<double>(), 0.0, 0.0};
  // Files written before the horizon was stored: three steps, as `stgf train --strides 1,2,3` trains.
  settings.normalisation.longest_interval = n.value("longest_interval", 3.0 * settings.normalisation.period);
  // Files written before the frame period was stored: s_t, the history spacing they were calibrated with.
  settings.normalisation.frame_period = n.value("frame_period", settings.normalisation.period);
  const MotionNormalisation& scales = settings.normalisation;
  for (const double scale : {scales.speed, scales.period, scales.length, scales.longest_interval, scales.frame_period}) {
    if (!(scale > 0.0) || !std::isfinite(scale)) throw std::invalid_argument("normalisation has a scale that is not positive");
  }
  const nlohmann::json& process_noise = config.at("process_noise");
  settings.process_noise_reference = matrix_from(process_noise.at("reference"));
  settings.process_noise_period = process_noise.at("period").get<double>();
  settings.process_noise_intervals =
      nodes_from(process_noise.value("intervals", nlohmann::json::array()), settings.process_noise_period);
  settings.coasting_process_noise = nodes_from(process_noise.value("coasting", nlohmann::json::array()), 0.0);
  settings.metadata = config.at("metadata");
  return settings;
}

std::vector<MotionNetworkParameter> motion_network_parameters(const MotionModelShape& shape) {
  const std::int64_t embedding = shape.embedding, hidden = shape.hidden, attention = shape.attention_hidden;
  std::vector<MotionNetworkParameter> parameters{
      {"embed.weight", {embedding, kMotionFeatures}},
      {"embed.bias", {embedding}},
      {"encoder.weight_ih_l0", {4 * hidden, embedding}},
      {"encoder.weight_hh_l0", {4 * hidden, hidden}},
      {"encoder.bias_ih_l0", {4 * hidden}},
      {"encoder.bias_hh_l0", {4 * hidden}}};
  for (const auto& [name, in, out] : {std::tuple{"attention1", hidden, attention}, std::tuple{"attention2", attention, hidden}}) {
    const std::string prefix(name);
    parameters.push_back({prefix + ".transform.weight", {out, in}});
    parameters.push_back({prefix + ".offset_transform.weight", {out, 3}});
    parameters.push_back({prefix + ".offset_transform.bias", {out}});
    parameters.push_back({prefix + ".score_self.weight", {1, out}});
    parameters.push_back({prefix + ".score_message.weight", {1, out}});
  }
  parameters.push_back({"decoder.weight_ih", {4 * hidden, 2 * hidden + 3}});
  parameters.push_back({"decoder.weight_hh", {4 * hidden, hidden}});
  parameters.push_back({"decoder.bias_ih", {4 * hidden}});
  parameters.push_back({"decoder.bias_hh", {4 * hidden}});
  parameters.push_back({"head.weight", {3, hidden}});
  parameters.push_back({"head.bias", {3}});
  return parameters;
}

const std::vector<float>& NamedWeights::at(const std::string& name) const {
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name) return values[k];
  }
  throw std::invalid_argument("the network has no weight '" + name + "'");
}

MotionNetworkWeights inference_weights(const MotionModelShape& shape, const NamedWeights& weights) {
  for (const MotionNetworkParameter& parameter : motion_network_parameters(shape)) {
    std::int64_t count = 1;
    for (const std::int64_t size : parameter.sizes) count *= size;
    if (static_cast<std::int64_t>(weights.at(parameter.name).size()) != count) {
      throw std::invalid_argument("weight '" + parameter.name + "' does not have the shape's size");
    }
  }
  const std::int64_t hidden = shape.hidden, attention = shape.attention_hidden;
  const auto lstm = [&](const std::string& prefix, const std::string& suffix, std::int64_t inputs) {
    // b = b_ih + b_hh, in single precision as LibTorch adds them.
    Eigen::VectorXf bias = vector_of(weights.at(prefix + ".bias_ih" + suffix));
    bias += vector_of(weights.at(prefix + ".bias_hh" + suffix));
    return MotionNetworkWeights::Lstm{matrix_of(weights.at(prefix + ".weight_ih" + suffix), 4 * hidden, inputs),
                                      matrix_of(weights.at(prefix + ".weight_hh" + suffix), 4 * hidden, hidden),
                                      std::move(bias)};
  };
  const auto graph_attention = [&](const std::string& prefix, std::int64_t in, std::int64_t out) {
    return MotionNetworkWeights::GraphAttention{
        matrix_of(weights.at(prefix + ".transform.weight"), out, in),
        matrix_of(weights.at(prefix + ".offset_transform.weight"), out, 3),
        vector_of(weights.at(prefix + ".offset_transform.bias")), vector_of(weights.at(prefix + ".score_self.weight")),
        vector_of(weights.at(prefix + ".score_message.weight"))};
  };
  MotionNetworkWeights result;
  result.embed = matrix_of(weights.at("embed.weight"), shape.embedding, kMotionFeatures);
  result.embed_bias = vector_of(weights.at("embed.bias"));
  result.encoder = lstm("encoder", "_l0", shape.embedding);
  result.attention1 = graph_attention("attention1", hidden, attention);
  result.attention2 = graph_attention("attention2", attention, hidden);
  result.decoder = lstm("decoder", "", 2 * hidden + 3);
  result.head = matrix_of(weights.at("head.weight"), 3, hidden);
  result.head_bias = vector_of(weights.at("head.bias"));
  return result;
}

std::string model_checksum(const std::string& config_text, const MotionModelShape& shape, const NamedWeights& weights) {
  Checksum checksum;
  checksum.add(config_text);
  for (const MotionNetworkParameter& parameter : motion_network_parameters(shape)) {
    const std::vector<float>& values = weights.at(parameter.name);
    checksum.add(parameter.name);
    for (const std::int64_t size : parameter.sizes) checksum.add(&size, sizeof size);
    checksum.add(values.data(), values.size() * sizeof(float));
  }
  return checksum.hex();
}

std::vector<std::vector<MotionForecast>> forecast_motion(const MotionInference& inference, const MotionModelShape& shape,
                                                         const MotionNormalisation& normalisation,
                                                         std::span<const MotionGraph> graphs) {
  if (graphs.empty()) return {};
  const MotionFeatures features = make_motion_features(graphs, shape, normalisation);
  std::vector<std::vector<MotionForecast>> forecasts(graphs.size());
  if (features.objects() == 0) return forecasts;
  const Eigen::Matrix3Xf acceleration = inference.accelerations(features);
  // â (m/s²) = s_v / s_t · head; x̂(τ) = p_last + (v_last + â Δt_last / 2) τ + â τ² / 2 (motion_model.hpp).
  const double scale = normalisation.speed / normalisation.period;
  for (std::size_t g = 0; g + 1 < features.graph_offsets.size(); ++g) {
    for (std::size_t i = features.graph_offsets[g]; i < features.graph_offsets[g + 1]; ++i) {
      MotionForecast forecast;
      forecast.acceleration = scale * acceleration.col(static_cast<Eigen::Index>(i)).cast<double>();
      forecast.velocity = features.last_velocities[i] + 0.5 * features.last_intervals[i] * forecast.acceleration;
      forecasts[g].push_back(forecast);
    }
  }
  return forecasts;
}

TrainedMotionModel::TrainedMotionModel(MotionModelSettings settings, const NamedWeights& weights)
    : settings_(std::move(settings)), inference_(inference_weights(settings_.shape, weights)) {}

std::vector<std::vector<MotionForecast>> TrainedMotionModel::forecast(std::span<const MotionGraph> graphs) const {
  return forecast_motion(inference_, settings_.shape, settings_.normalisation, graphs);
}

Matrix3d TrainedMotionModel::process_noise(double dt) const {
  return process_noise_at(settings_.process_noise_reference, settings_.process_noise_period,
                          settings_.process_noise_intervals, dt);
}

Matrix3d TrainedMotionModel::coasting_process_noise(double dt) const {
  if (settings_.coasting_process_noise.empty()) return process_noise(dt);
  return coasting_process_noise_at(settings_.coasting_process_noise, dt);
}

double motion_model_coasting_horizon(const MotionNormalisation& normalisation,
                                     std::span<const IntervalNoise> coasting_process_noise) {
  const double horizon = kHorizonFactor * normalisation.longest_interval;
  if (coasting_process_noise.empty()) return horizon;
  return std::max(horizon, kHorizonFactor * coasting_process_noise.back().interval);
}

double motion_model_widest_history_spacing(const MotionNormalisation& normalisation, double process_noise_period,
                                           std::span<const IntervalNoise> process_noise_intervals,
                                           std::span<const IntervalNoise> coasting_process_noise) {
  if (coasting_process_noise.empty()) return std::numeric_limits<double>::infinity();
  const double forecast_end =
      process_noise_intervals.empty() ? process_noise_period : process_noise_intervals.back().interval;
  return std::min(kCoastingStartFactor * normalisation.longest_interval,
                  std::sqrt(forecast_end * coasting_process_noise.front().interval));
}

TrainedMotionModel TrainedMotionModel::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "no such model file");
  std::ifstream file(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (!file && !file.eof()) throw InputError(path, 0, "cannot read the model file");
  return parse(bytes, path);
}

TrainedMotionModel TrainedMotionModel::parse(const std::string& bytes, const std::string& path) {
  TorchArchive archive;
  try {
    archive = TorchArchive::parse(bytes);
  } catch (const std::invalid_argument& error) {
    throw InputError(path, 0, std::string("not a readable model file (corrupt, or not written by stgf train): ") +
                                  error.what());
  }
  const auto string_value = [&](const TorchArchive& in, const std::string& key) -> const std::string* {
    const TorchArchive::Value* value = in.find(key);
    return value != nullptr ? std::get_if<std::string>(value) : nullptr;
  };
  const std::string* format = string_value(archive, "format");
  if (format == nullptr || *format != kMotionModelFormat) {
    throw InputError(path, 0, "not a stgf motion model (no '" + std::string(kMotionModelFormat) + "' marker)");
  }
  const TorchArchive::Value* version_value = archive.find("version");
  const std::int64_t* version = version_value != nullptr ? std::get_if<std::int64_t>(version_value) : nullptr;
  if (version == nullptr || *version < 1 || *version > kMotionModelVersion) {
    throw InputError(path, 0, "model file version is not 1 to " + std::to_string(kMotionModelVersion));
  }
  const std::string* config_text = string_value(archive, "config");
  MotionModelSettings settings;
  try {
    if (config_text == nullptr) throw std::invalid_argument("no config");
    settings = settings_from_json(nlohmann::json::parse(*config_text));
  } catch (const std::exception& error) {
    throw InputError(path, 0, std::string("model configuration is invalid: ") + error.what());
  }
  // Every weight the stated shape has, by name through the nested archives ("attention1.transform.weight").
  const TorchArchive::Value* network_value = archive.find("network");
  const auto* network = network_value != nullptr ? std::get_if<std::shared_ptr<const TorchArchive>>(network_value) : nullptr;
  if (network == nullptr) throw InputError(path, 0, "model weights are missing or unreadable: no network");
  NamedWeights weights;
  for (const MotionNetworkParameter& parameter : motion_network_parameters(settings.shape)) {
    const TorchArchive* level = network->get();
    std::string rest = parameter.name;
    const TorchArchive::Value* value = nullptr;
    for (std::size_t dot; level != nullptr && (dot = rest.find('.')) != std::string::npos; rest = rest.substr(dot + 1)) {
      const TorchArchive::Value* nested = level->find(rest.substr(0, dot));
      const auto* archive_pointer = nested != nullptr ? std::get_if<std::shared_ptr<const TorchArchive>>(nested) : nullptr;
      level = archive_pointer != nullptr ? archive_pointer->get() : nullptr;
    }
    if (level != nullptr) value = level->find(rest);
    const auto* tensor = value != nullptr ? std::get_if<ArchiveTensor>(value) : nullptr;
    if (tensor == nullptr) {
      throw InputError(path, 0, "model weights are missing or unreadable: no parameter '" + parameter.name + "'");
    }
    if (tensor->sizes != parameter.sizes) {
      throw InputError(path, 0, "model weights do not match its stated shape (parameter '" + parameter.name + "')");
    }
    for (const float x : tensor->values) {
      if (!std::isfinite(x)) throw InputError(path, 0, "model parameter '" + parameter.name + "' is not finite");
    }
    weights.names.push_back(parameter.name);
    weights.values.push_back(tensor->values);
  }
  if (!settings.process_noise_reference.allFinite() || !(settings.process_noise_period > 0.0)) {
    throw InputError(path, 0, "model process noise is invalid");
  }
  if (*version >= 2) {
    const std::string* stored = string_value(archive, "checksum");
    if (stored == nullptr) throw InputError(path, 0, "model file has no checksum");
    if (*stored != model_checksum(*config_text, settings.shape, weights)) {
      throw InputError(path, 0, "model file is corrupt: its weights or settings do not match its checksum");
    }
  }
  return TrainedMotionModel(std::move(settings), weights);
}

}  // namespace stgf
