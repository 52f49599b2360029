// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/motion_model.hpp"

#include <algorithm>
#include <iterator>
#include <cmath>
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

// The network's weights by name, in its parameter order, as the LibTorch-free side reads them
// (trained_motion_model.hpp).
// With `float16`, the values as a file stored with float16 weights gives them back.
NamedWeights named_weights(const detail::MotionNetwork& network, bool float16 = false) {
  NamedWeights weights;
  for (const auto& item : network->named_parameters()) {
    torch::Tensor values = item.value().detach().contiguous();
    if (float16) values = values.to(torch::kHalf);
    values = values.to(torch::kFloat32);
    weights.names.push_back(item.key());
    weights.values.emplace_back(values.data_ptr<float>(), values.data_ptr<float>() + values.numel());
  }
  return weights;
}

// Module::save, with every parameter written as float16 (half the file; the network itself untouched).
void save_as_float16(const torch::nn::Module& module, torch::serialize::OutputArchive& archive) {
  for (const auto& parameter : module.named_parameters(/*recurse=*/false)) {
    archive.write(parameter.key(), parameter.value().detach().to(torch::kHalf));
  }
  for (const auto& buffer : module.named_buffers(/*recurse=*/false)) archive.write(buffer.key(), buffer.value(), true);
  for (const auto& child : module.named_children()) {
    torch::serialize::OutputArchive child_archive(archive.compilation_unit());
    save_as_float16(*child.value(), child_archive);
    archive.write(child.key(), child_archive);
  }
}

// Module::load for weights stored as float32 or float16 (LibTorch's own would turn a float32 parameter
// into a float16 one): each stored tensor is copied into its parameter, converted. True when any
// was stored as float16.
bool load_weights(torch::nn::Module& module, torch::serialize::InputArchive& archive) {
  bool float16 = false;
  torch::NoGradGuard no_grad;
  const auto copy_into = [&](const std::string& key, torch::Tensor& into, bool is_buffer) {
    torch::Tensor stored;
    archive.read(key, stored, is_buffer);
    if (stored.sizes() != into.sizes()) throw std::runtime_error("weight " + key + " has the wrong shape");
    float16 = float16 || stored.scalar_type() == torch::kHalf;
    into.copy_(stored);
  };
  for (auto& parameter : module.named_parameters(/*recurse=*/false)) copy_into(parameter.key(), parameter.value(), false);
  for (auto& buffer : module.named_buffers(/*recurse=*/false)) copy_into(buffer.key(), buffer.value(), true);
  for (const auto& child : module.named_children()) {
    torch::serialize::InputArchive child_archive;
    archive.read(child.key(), child_archive);
    float16 = load_weights(*child.value(), child_archive) || float16;
  }
  return float16;
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
  MotionModelSettings settings{shape, normalisation, process_noise_reference, process_noise_period,
                               extra_metadata.is_null() ? metadata : extra_metadata, process_noise_intervals,
                               coasting_process_noise};
  const nlohmann::json config = settings_json(settings);
  const std::string config_text = config.dump();
  torch::serialize::OutputArchive archive;
  archive.write("format", c10::IValue(std::string(kMotionModelFormat)));
  archive.write("version", c10::IValue(static_cast<int64_t>(kMotionModelVersion)));
  archive.write("config", c10::IValue(config_text));
  archive.write("checksum", c10::IValue(model_checksum(config_text, shape, named_weights(network, weights_float16))));
  torch::serialize::OutputArchive network_archive;
  if (weights_float16) {
    save_as_float16(*network, network_archive);
  } else {
    network->save(network_archive);
  }
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
  // Read once: checked without LibTorch (every check a model file gets, the archive's own included:
  // LibTorch's parser crashes on some damaged archives, found by fuzz_model_file), then parsed by
  // LibTorch from the same bytes for the network's tensors.
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const TrainedMotionModel checked = TrainedMotionModel::parse(bytes, path);
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(bytes.data(), bytes.size());
  } catch (const c10::Error&) {
    throw InputError(path, 0, "not a readable model file (corrupt, or not written by stgf train)");
  }
  auto impl = std::make_unique<Impl>();
  const MotionModelSettings& settings = checked.settings();
  impl->shape = settings.shape;
  impl->normalisation = settings.normalisation;
  impl->process_noise_reference = settings.process_noise_reference;
  impl->process_noise_period = settings.process_noise_period;
  impl->process_noise_intervals = settings.process_noise_intervals;
  impl->coasting_process_noise = settings.coasting_process_noise;
  impl->metadata = settings.metadata;
  impl->network = detail::MotionNetwork(impl->shape);
  try {
    torch::serialize::InputArchive network_archive;
    archive.read("network", network_archive);
    impl->weights_float16 = load_weights(*impl->network, network_archive);
  } catch (const std::runtime_error& error) {
    throw InputError(path, 0, std::string("model weights are unreadable: ") + first_line(error.what()));
  } catch (const c10::Error& error) {
    throw InputError(path, 0, std::string("model weights are missing or unreadable: ") + error.what_without_backtrace());
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

std::shared_ptr<const MotionInference> MotionModel::Impl::inference() const {
  // Every in-place change of a parameter (an optimizer step, a load) bumps its version counter.
  std::int64_t version = 0;
  for (const torch::Tensor& parameter : network->parameters()) version += static_cast<std::int64_t>(parameter._version());
  const std::lock_guard lock(inference_mutex_);
  if (!inference_ || version != inference_weights_version_) {
    inference_ = std::make_shared<const MotionInference>(inference_weights(shape, named_weights(network, weights_float16)));
    inference_weights_version_ = version;
  }
  return inference_;
}

std::vector<std::vector<MotionForecast>> MotionModel::forecast(std::span<const MotionGraph> graphs) const {
  if (graphs.empty()) return {};
  return forecast_motion(*impl_->inference(), impl_->shape, impl_->normalisation, graphs);
}

TrainedMotionModel MotionModel::trained() const {
  return TrainedMotionModel(MotionModelSettings{impl_->shape, impl_->normalisation, impl_->process_noise_reference,
                                                impl_->process_noise_period, impl_->metadata,
                                                impl_->process_noise_intervals, impl_->coasting_process_noise},
                            named_weights(impl_->network, impl_->weights_float16));
}

Matrix3d MotionModel::process_noise(double dt) const {
  return process_noise_at(impl_->process_noise_reference, impl_->process_noise_period, impl_->process_noise_intervals,
                          dt);
}

double MotionModel::widest_history_spacing() const {
  return motion_model_widest_history_spacing(impl_->normalisation, impl_->process_noise_period,
                                             impl_->process_noise_intervals, impl_->coasting_process_noise);
}

double MotionModel::coasting_horizon() const {
  return motion_model_coasting_horizon(impl_->normalisation, impl_->coasting_process_noise);
}

Matrix3d MotionModel::coasting_process_noise(double dt) const {
  if (impl_->coasting_process_noise.empty()) return process_noise(dt);
  return coasting_process_noise_at(impl_->coasting_process_noise, dt);
}

void MotionModel::set_process_noise(const Matrix3d& reference, double reference_period) {
  if (!reference.allFinite() || !(reference_period > 0.0)) throw std::invalid_argument("process noise is invalid");
  impl_->process_noise_reference = reference;
  impl_->process_noise_period = reference_period;
  impl_->process_noise_intervals.clear();
  impl_->coasting_process_noise.clear();
}

void MotionModel::set_process_noise_intervals(std::vector<IntervalNoise> intervals, std::vector<IntervalNoise> coasting) {
  check_process_noise_nodes(intervals, impl_->process_noise_period);
  check_process_noise_nodes(coasting, 0.0);
  impl_->process_noise_intervals = std::move(intervals);
  impl_->coasting_process_noise = std::move(coasting);
}

double MotionModel::process_noise_period() const { return impl_->process_noise_period; }

const std::vector<IntervalNoise>& MotionModel::process_noise_intervals() const {
  return impl_->process_noise_intervals;
}

const std::vector<IntervalNoise>& MotionModel::coasting_process_noise_intervals() const {
  return impl_->coasting_process_noise;
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
