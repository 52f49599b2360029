// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/motion_model.hpp"

#include <algorithm>
#include <optional>
#include <iterator>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "stgf/io/input_error.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/learn/motion_network.hpp"

namespace stgf {
namespace detail {
namespace {

torch::Tensor float_tensor(const std::vector<float>& values, std::vector<int64_t> shape) {
  return torch::from_blob(const_cast<float*>(values.data()), shape, torch::kFloat32).clone();
}

}  // namespace

MotionBatch make_motion_batch(std::span<const MotionGraph> graphs, const MotionModelShape& shape,
                              const MotionNormalisation& normalisation) {
  MotionBatch batch{make_motion_features(graphs, shape, normalisation), {}};
  const auto n = static_cast<int64_t>(batch.objects());
  const auto edges = static_cast<int64_t>(batch.edges());
  batch.tensors.motion = float_tensor(batch.motion, {n, batch.history, kMotionFeatures});
  batch.tensors.last_velocity = float_tensor(batch.last_velocity, {n, 3});
  batch.tensors.horizon = float_tensor(batch.horizon, {n, 1});
  batch.tensors.last_interval = float_tensor(batch.last_interval, {n, 1});
  batch.tensors.edge_source = torch::from_blob(batch.edge_source.data(), {edges}, torch::kInt64).clone();
  batch.tensors.edge_target = torch::from_blob(batch.edge_target.data(), {edges}, torch::kInt64).clone();
  batch.tensors.edge_offset = float_tensor(batch.edge_offset, {edges, 3});
  return batch;
}

GraphAttentionImpl::GraphAttentionImpl(int in_features, int out_features)
    : transform_(register_module("transform", torch::nn::Linear(torch::nn::LinearOptions(in_features, out_features).bias(false)))),
      offset_transform_(register_module("offset_transform", torch::nn::Linear(3, out_features))),
      score_self_(register_module("score_self", torch::nn::Linear(torch::nn::LinearOptions(out_features, 1).bias(false)))),
      score_message_(register_module("score_message", torch::nn::Linear(torch::nn::LinearOptions(out_features, 1).bias(false)))) {}

torch::Tensor GraphAttentionImpl::forward(const torch::Tensor& h, const torch::Tensor& source,
                                          const torch::Tensor& target, const torch::Tensor& offset) {
  const int64_t n = h.size(0);
  const torch::Tensor wh = transform_(h);                                                  // W h
  const torch::Tensor message = wh.index_select(0, source) + offset_transform_(offset);   // [E, out]
  const torch::Tensor score = torch::leaky_relu(score_self_(wh).index_select(0, target) + score_message_(message), 0.2)
                                  .squeeze(1);                                             // [E]
  // Softmax over the edges that end at the same object. Scores are clamped to ±30 so exp cannot
  // overflow (e^60 is already a certainty in a softmax), which spares the per-object max shift.
  const torch::Tensor weight = score.clamp(-30.0, 30.0).exp();
  const torch::Tensor total = torch::zeros({n}, score.options()).index_add(0, target, weight);
  const torch::Tensor alpha = weight / total.index_select(0, target);
  const torch::Tensor aggregated =
      torch::zeros({n, message.size(1)}, message.options()).index_add(0, target, message * alpha.unsqueeze(1));
  return torch::elu(aggregated);
}

MotionNetworkImpl::MotionNetworkImpl(const MotionModelShape& shape)
    : embed_(register_module("embed", torch::nn::Linear(kMotionFeatures, shape.embedding))),
      encoder_(register_module(
          "encoder", torch::nn::LSTM(torch::nn::LSTMOptions(shape.embedding, shape.hidden).batch_first(true)))),
      attention1_(register_module("attention1", GraphAttention(shape.hidden, shape.attention_hidden))),
      attention2_(register_module("attention2", GraphAttention(shape.attention_hidden, shape.hidden))),
      decoder_(register_module("decoder", torch::nn::LSTMCell(2 * shape.hidden + 3, shape.hidden))),
      head_(register_module("head", torch::nn::Linear(shape.hidden, 3))) {
  // A small head: the untrained network is close to the constant-velocity model.
  torch::NoGradGuard no_grad;
  head_->weight.mul_(0.01);
  head_->bias.zero_();
}

torch::Tensor MotionNetworkImpl::forward(const MotionBatch& batch) {
  // v̂ = v_last + â (Δt_last + Δt) / 2: the head predicts an acceleration â, and v_last, measured
  // over the last interval, lags the current velocity by half of it.
  return batch.tensors.last_velocity + acceleration(batch) * (0.5 * (batch.tensors.last_interval + batch.tensors.horizon));
}

torch::Tensor MotionNetworkImpl::acceleration(const MotionBatch& batch) {
  const torch::Tensor embedded = torch::relu(embed_(batch.tensors.motion));                 // [N, H, E]
  const auto [sequence, state] = encoder_(embedded);
  const torch::Tensor motion_embedding = std::get<0>(state).squeeze(0);            // m: [N, hidden]
  const torch::Tensor cell = std::get<1>(state).squeeze(0);
  const torch::Tensor spatial = attention2_(
      attention1_(motion_embedding, batch.tensors.edge_source, batch.tensors.edge_target, batch.tensors.edge_offset), batch.tensors.edge_source,
      batch.tensors.edge_target, batch.tensors.edge_offset);                                        // s: [N, hidden]
  const torch::Tensor input = torch::cat({motion_embedding, spatial, batch.tensors.last_velocity}, 1);
  const auto [decoded, decoded_cell] = decoder_(input, std::make_tuple(motion_embedding, cell));
  return head_(decoded);
}

}  // namespace detail

// ── MotionModel ────────────────────────────────────────────────────────────────────────────────────

namespace {

constexpr const char* kFormat = "stgf-motion-model";
// 1: the first format. 2: adds "checksum" (required) and stores Adam's state under "adam" keyed by
// parameter index. Version 1 files are still read (without the check).
constexpr int kFormatVersion = 2;

// FNV-1a, 64 bit: the model file's integrity check over its configuration text and every weight's
// name, shape and bytes, in the network's parameter order. It catches corruption (a flipped byte
// anywhere in them), not tampering.
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

std::string weights_checksum(const std::string& config_text, const detail::MotionNetwork& network) {
  Checksum checksum;
  checksum.add(config_text);
  for (const auto& item : network->named_parameters()) {
    const torch::Tensor values = item.value().detach().contiguous().to(torch::kFloat32);
    checksum.add(item.key());
    for (const int64_t size : values.sizes()) checksum.add(&size, sizeof size);
    checksum.add(values.data_ptr<float>(), static_cast<std::size_t>(values.numel()) * sizeof(float));
  }
  return checksum.hex();
}

// Adam's state, keyed by parameter index. (LibTorch's Optimizer::save keys it by each parameter's
// heap address, so two identical trainings wrote different bytes.)
void save_adam_state(torch::optim::Optimizer& optimizer, torch::serialize::OutputArchive& archive) {
  const std::vector<torch::Tensor>& parameters = optimizer.param_groups().at(0).params();
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const auto found = optimizer.state().find(c10::guts::to_string(parameters[k].unsafeGetTensorImpl()));
    if (found == optimizer.state().end()) continue;
    const auto* adam = dynamic_cast<const torch::optim::AdamParamState*>(found->second.get());
    if (adam == nullptr) throw std::logic_error("save_adam_state: the optimizer is not Adam");
    const std::string prefix = std::to_string(k) + "/";
    archive.write(prefix + "step", c10::IValue(adam->step()));
    archive.write(prefix + "exp_avg", adam->exp_avg());
    archive.write(prefix + "exp_avg_sq", adam->exp_avg_sq());
    if (adam->max_exp_avg_sq().defined()) archive.write(prefix + "max_exp_avg_sq", adam->max_exp_avg_sq());
  }
}

void load_adam_state(torch::serialize::InputArchive& archive, torch::optim::Optimizer& optimizer) {
  const std::vector<torch::Tensor>& parameters = optimizer.param_groups().at(0).params();
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const std::string prefix = std::to_string(k) + "/";
    c10::IValue step;
    if (!archive.try_read(prefix + "step", step)) continue;
    auto state = std::make_unique<torch::optim::AdamParamState>();
    state->step(step.toInt());
    torch::Tensor exp_avg, exp_avg_sq, max_exp_avg_sq;
    archive.read(prefix + "exp_avg", exp_avg);
    archive.read(prefix + "exp_avg_sq", exp_avg_sq);
    state->exp_avg(exp_avg);
    state->exp_avg_sq(exp_avg_sq);
    if (archive.try_read(prefix + "max_exp_avg_sq", max_exp_avg_sq)) state->max_exp_avg_sq(max_exp_avg_sq);
    optimizer.state()[c10::guts::to_string(parameters[k].unsafeGetTensorImpl())] = std::move(state);
  }
}

nlohmann::json shape_json(const MotionModelShape& s) {
  return {{"history_length", s.history_length}, {"embedding", s.embedding}, {"hidden", s.hidden},
          {"attention_hidden", s.attention_hidden}, {"max_fully_connected", s.max_fully_connected},
          {"nearest_neighbours", s.nearest_neighbours}};
}

MotionModelShape shape_from(const nlohmann::json& j) {
  MotionModelShape s;
  s.history_length = j.at("history_length").get<int>();
  s.embedding = j.at("embedding").get<int>();
  s.hidden = j.at("hidden").get<int>();
  s.attention_hidden = j.at("attention_hidden").get<int>();
  s.max_fully_connected = j.at("max_fully_connected").get<int>();
  s.nearest_neighbours = j.at("nearest_neighbours").get<int>();
  if (s.history_length < 1 || s.embedding < 1 || s.hidden < 1 || s.attention_hidden < 1 ||
      s.max_fully_connected < 1 || s.nearest_neighbours < 1) {
    throw std::invalid_argument("shape has a size below 1");
  }
  return s;
}

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

}  // namespace

MotionModel::MotionModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

MotionModel::MotionModel(const MotionModelShape& shape, const MotionNormalisation& normalisation, std::uint64_t seed)
    : impl_(std::make_unique<Impl>()) {
  torch::manual_seed(seed);
  impl_->shape = shape;
  impl_->normalisation = normalisation;
  impl_->network = detail::MotionNetwork(shape);
}

MotionModel::~MotionModel() = default;
MotionModel::MotionModel(MotionModel&&) noexcept = default;
MotionModel& MotionModel::operator=(MotionModel&&) noexcept = default;

void MotionModel::Impl::save(const std::string& path, const nlohmann::json& extra_metadata,
                             torch::optim::Optimizer* optimizer) const {
  nlohmann::json config = {
      {"shape", shape_json(shape)},
      {"normalisation",
       {{"speed", normalisation.speed},
        {"period", normalisation.period},
        {"length", normalisation.length},
        {"longest_interval", normalisation.longest_interval}}},
      {"process_noise", {{"reference", matrix_json(process_noise_reference)}, {"period", process_noise_period}}},
      {"metadata", extra_metadata.is_null() ? metadata : extra_metadata}};
  const std::string config_text = config.dump();
  torch::serialize::OutputArchive archive;
  archive.write("format", c10::IValue(std::string(kFormat)));
  archive.write("version", c10::IValue(static_cast<int64_t>(kFormatVersion)));
  archive.write("config", c10::IValue(config_text));
  archive.write("checksum", c10::IValue(weights_checksum(config_text, network)));
  torch::serialize::OutputArchive network_archive;
  network->save(network_archive);
  archive.write("network", network_archive);
  if (optimizer != nullptr) {
    torch::serialize::OutputArchive optimizer_archive;
    save_adam_state(*optimizer, optimizer_archive);
    archive.write("adam", optimizer_archive);
  }
  // Whole or not at all (OutputFile). Through a stream, because saving to a file name makes the
  // archive's record names start with that name (the temporary's, with a process id): the same model
  // would give different bytes.
  OutputFile file(path);
  try {
    archive.save_to(file.stream());
  } catch (const c10::Error& error) {
    throw std::runtime_error(path + ": cannot write the model: " + error.what_without_backtrace());
  }
  file.commit();
}

void MotionModel::save(const std::string& path, const nlohmann::json& metadata) const {
  impl_->save(path, metadata, nullptr);
}

namespace {

std::uint32_t crc32(const unsigned char* data, std::size_t size) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFU;
}

// Why the zip archive `bytes` is damaged, or nullopt: every record listed in its central directory
// lies inside the file and matches its CRC-32. LibTorch's TorchScript parser crashes (a segmentation
// fault, which nothing can catch) on some damaged archives (found by fuzz_model_file), so stgf checks
// the bytes before LibTorch parses them. Archives it cannot check (ZIP64, compressed records) pass.
std::optional<std::string> zip_damage(const std::string& bytes) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  const auto u16 = [&](std::size_t at) { return static_cast<std::uint32_t>(data[at] | data[at + 1] << 8); };
  const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
  if (size < 22) return "too short for a zip archive";
  std::size_t end = size - 22;  // the end-of-central-directory record, after at most a 64 KB comment
  while (u32(end) != 0x06054b50U) {
    if (end == 0 || size - end > 22 + 65535) return "no zip directory";
    --end;
  }
  const std::size_t entries = u16(end + 10);
  std::size_t at = u32(end + 16);
  if (u32(end + 16) == 0xFFFFFFFFU || entries == 0xFFFFU) return std::nullopt;  // ZIP64
  for (std::size_t k = 0; k < entries; ++k) {
    if (at + 46 > size || u32(at) != 0x02014b50U) return "damaged zip directory";
    const std::uint32_t method = u16(at + 10), crc = u32(at + 16), stored = u32(at + 20);
    const std::size_t name_length = u16(at + 28);
    const std::size_t local = u32(at + 42);
    if (at + 46 + name_length > size) return "damaged zip directory";
    const std::string name = bytes.substr(at + 46, std::min<std::size_t>(name_length, 80));
    if (stored == 0xFFFFFFFFU || local == 0xFFFFFFFFU) return std::nullopt;  // ZIP64
    if (local + 30 > size || u32(local) != 0x04034b50U) return "record '" + name + "' is not where the directory says";
    const std::size_t start = local + 30 + u16(local + 26) + u16(local + 28);
    if (start + stored > size) return "record '" + name + "' runs past the end of the file";
    if (method == 0 && crc32(data + start, stored) != crc) return "record '" + name + "' fails its CRC-32";
    at += 46 + name_length + u16(at + 30) + u16(at + 32);
  }
  return std::nullopt;
}

// The first line of a LibTorch error, at most 120 characters (its messages carry source excerpts
// and backtraces).
std::string first_line(const char* what) {
  std::string text(what);
  text = text.substr(0, text.find('\n'));
  return text.size() > 120 ? text.substr(0, 117) + "..." : text;
}

}  // namespace

MotionModel MotionModel::load(const std::string& path) {
  // Whatever LibTorch throws on a damaged archive (c10::Error, TorchScript parse errors found by
  // fuzz_model_file, …) is an input error naming the file.
  try {
    return load_checked(path);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& error) {
    throw InputError(path, 0, "not a readable model file (corrupt, or not written by stgf train): " +
                                  first_line(error.what()));
  }
}

MotionModel MotionModel::load_checked(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, 0, "no such model file");
  // Read once: checked here, then parsed by LibTorch from the same bytes.
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (const auto damage = zip_damage(bytes)) {
    throw InputError(path, 0, "not a readable model file (corrupt, or not written by stgf train): " + *damage);
  }
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(bytes.data(), bytes.size());
  } catch (const c10::Error&) {
    throw InputError(path, 0, "not a readable model file (corrupt, or not written by stgf train)");
  }
  c10::IValue format, config_text;
  if (!archive.try_read("format", format) || !format.isString() || format.toStringRef() != kFormat) {
    throw InputError(path, 0, "not a stgf motion model (no '" + std::string(kFormat) + "' marker)");
  }
  c10::IValue version;
  if (!archive.try_read("version", version) || !version.isInt() || version.toInt() < 1 ||
      version.toInt() > kFormatVersion) {
    throw InputError(path, 0, "model file version is not 1 to " + std::to_string(kFormatVersion));
  }
  auto impl = std::make_unique<Impl>();
  try {
    archive.read("config", config_text);
    const nlohmann::json config = nlohmann::json::parse(config_text.toStringRef());
    impl->shape = shape_from(config.at("shape"));
    const auto& n = config.at("normalisation");
    impl->normalisation = {n.at("speed").get<double>(), n.at("period").get<double>(), n.at("length").get<double>(),
                           0.0};
    // Files written before the horizon was stored: three steps, as `stgf train --strides 1,2,3` trains.
    impl->normalisation.longest_interval = n.value("longest_interval", 3.0 * impl->normalisation.period);
    impl->process_noise_reference = matrix_from(config.at("process_noise").at("reference"));
    impl->process_noise_period = config.at("process_noise").at("period").get<double>();
    impl->metadata = config.at("metadata");
  } catch (const std::exception& error) {
    throw InputError(path, 0, std::string("model configuration is invalid: ") + error.what());
  }
  impl->network = detail::MotionNetwork(impl->shape);
  // Module::load would adopt whatever shapes the file holds; check them against the stated shape.
  std::vector<std::pair<std::string, std::vector<int64_t>>> expected;
  for (const auto& item : impl->network->named_parameters()) {
    expected.emplace_back(item.key(), item.value().sizes().vec());
  }
  try {
    torch::serialize::InputArchive network_archive;
    archive.read("network", network_archive);
    impl->network->load(network_archive);
  } catch (const c10::Error& error) {
    throw InputError(path, 0, std::string("model weights are missing or unreadable: ") + error.what_without_backtrace());
  }
  const auto parameters = impl->network->named_parameters();
  for (const auto& [name, sizes] : expected) {
    const torch::Tensor* loaded = parameters.find(name);
    if (loaded == nullptr || loaded->sizes().vec() != sizes) {
      throw InputError(path, 0, "model weights do not match its stated shape (parameter '" + name + "')");
    }
    if (!torch::isfinite(*loaded).all().item<bool>()) {
      throw InputError(path, 0, "model parameter '" + name + "' is not finite");
    }
  }
  if (!impl->process_noise_reference.allFinite() || !(impl->process_noise_period > 0.0)) {
    throw InputError(path, 0, "model process noise is invalid");
  }
  if (version.toInt() >= 2) {
    c10::IValue stored;
    if (!archive.try_read("checksum", stored) || !stored.isString()) throw InputError(path, 0, "model file has no checksum");
    if (stored.toStringRef() != weights_checksum(config_text.toStringRef(), impl->network)) {
      throw InputError(path, 0, "model file is corrupt: its weights or settings do not match its checksum");
    }
  }
  return MotionModel(std::move(impl));
}

std::vector<std::vector<Vector3d>> MotionModel::Impl::positions_from(const detail::MotionBatch& batch,
                                                                   const torch::Tensor& velocity) const {
  const torch::Tensor v = velocity.to(torch::kFloat64).contiguous();
  const double* values = v.data_ptr<double>();
  std::vector<std::vector<Vector3d>> positions(batch.graph_offsets.size() - 1);
  for (std::size_t g = 0; g + 1 < batch.graph_offsets.size(); ++g) {
    for (std::size_t i = batch.graph_offsets[g]; i < batch.graph_offsets[g + 1]; ++i) {
      const Vector3d predicted_velocity =
          normalisation.speed * Vector3d(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
      positions[g].push_back(batch.last_positions[i] + predicted_velocity * batch.horizons[i]);
    }
  }
  return positions;
}

std::vector<std::vector<MotionForecast>> MotionModel::Impl::forecasts_from(const MotionFeatures& features,
                                                                       const Eigen::Matrix3Xf& acceleration) const {
  // â (m/s²) = s_v / s_t · head; x̂(τ) = p_last + (v_last + â Δt_last / 2) τ + â τ² / 2 (motion_model.hpp).
  const double scale = normalisation.speed / normalisation.period;
  std::vector<std::vector<MotionForecast>> forecasts(features.graph_offsets.size() - 1);
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

namespace {

Eigen::MatrixXf matrix_of(const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.detach().to(torch::kFloat32).contiguous();
  const auto rows = values.size(0);
  const auto cols = values.dim() > 1 ? values.size(1) : 1;
  // LibTorch is row-major.
  return Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      values.data_ptr<float>(), rows, cols);
}

Eigen::VectorXf vector_of(const torch::Tensor& tensor) {
  const torch::Tensor values = tensor.detach().to(torch::kFloat32).contiguous().reshape({-1});
  return Eigen::Map<const Eigen::VectorXf>(values.data_ptr<float>(), values.size(0));
}

// The network's weights by their LibTorch names (motion_network.hpp registers them).
MotionNetworkWeights weights_of(const detail::MotionNetwork& network) {
  const auto parameters = network->named_parameters();
  const auto get = [&](const std::string& name) {
    const torch::Tensor* found = parameters.find(name);
    if (found == nullptr) throw std::logic_error("motion network has no parameter " + name);
    return *found;
  };
  const auto lstm = [&](const std::string& prefix, const std::string& suffix) {
    return MotionNetworkWeights::Lstm{matrix_of(get(prefix + ".weight_ih" + suffix)),
                                      matrix_of(get(prefix + ".weight_hh" + suffix)),
                                      vector_of(get(prefix + ".bias_ih" + suffix) + get(prefix + ".bias_hh" + suffix))};
  };
  const auto attention = [&](const std::string& prefix) {
    return MotionNetworkWeights::GraphAttention{
        matrix_of(get(prefix + ".transform.weight")), matrix_of(get(prefix + ".offset_transform.weight")),
        vector_of(get(prefix + ".offset_transform.bias")), vector_of(get(prefix + ".score_self.weight")),
        vector_of(get(prefix + ".score_message.weight"))};
  };
  MotionNetworkWeights weights;
  weights.embed = matrix_of(get("embed.weight"));
  weights.embed_bias = vector_of(get("embed.bias"));
  weights.encoder = lstm("encoder", "_l0");
  weights.attention1 = attention("attention1");
  weights.attention2 = attention("attention2");
  weights.decoder = lstm("decoder", "");
  weights.head = matrix_of(get("head.weight"));
  weights.head_bias = vector_of(get("head.bias"));
  return weights;
}

}  // namespace

std::shared_ptr<const MotionInference> MotionModel::Impl::inference() const {
  // Every in-place change of a parameter (an optimizer step, a load) bumps its version counter.
  std::int64_t version = 0;
  for (const torch::Tensor& parameter : network->parameters()) version += static_cast<std::int64_t>(parameter._version());
  const std::lock_guard lock(inference_mutex_);
  if (!inference_ || version != inference_weights_version_) {
    inference_ = std::make_shared<const MotionInference>(weights_of(network));
    inference_weights_version_ = version;
  }
  return inference_;
}

std::vector<std::vector<MotionForecast>> MotionModel::forecast(std::span<const MotionGraph> graphs) const {
  if (graphs.empty()) return {};
  const MotionFeatures features = make_motion_features(graphs, impl_->shape, impl_->normalisation);
  if (features.objects() == 0) return std::vector<std::vector<MotionForecast>>(graphs.size());
  return impl_->forecasts_from(features, impl_->inference()->accelerations(features));
}

Matrix3d MotionModel::process_noise(double dt) const {
  const double ratio = dt / impl_->process_noise_period;
  return impl_->process_noise_reference * (ratio * ratio);
}

void MotionModel::set_process_noise(const Matrix3d& reference, double reference_period) {
  if (!reference.allFinite() || !(reference_period > 0.0)) throw std::invalid_argument("process noise is invalid");
  impl_->process_noise_reference = reference;
  impl_->process_noise_period = reference_period;
}

const MotionModelShape& MotionModel::shape() const { return impl_->shape; }
const MotionNormalisation& MotionModel::normalisation() const { return impl_->normalisation; }
nlohmann::json MotionModel::metadata() const { return impl_->metadata; }

bool load_optimizer_state(const std::string& path, torch::optim::Optimizer& optimizer) {
  torch::serialize::InputArchive archive;
  archive.load_from(path);
  torch::serialize::InputArchive optimizer_archive;
  if (archive.try_read("adam", optimizer_archive)) {
    load_adam_state(optimizer_archive, optimizer);
    return true;
  }
  if (!archive.try_read("optimizer", optimizer_archive)) return false;  // version 1
  optimizer.load(optimizer_archive);
  return true;
}

}  // namespace stgf
