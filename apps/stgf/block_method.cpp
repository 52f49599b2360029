// SPDX-License-Identifier: Apache-2.0
#include "block_method.hpp"

#include "gating_log.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf::cli {
namespace {

// Each scene alone (run_localizer), so any block of whole scenes gives the estimates of the whole
// file; the gate's summary adds up over the blocks in scene order, as over the whole file.
class ModelFreeMethod final : public BlockMethod {
 public:
  ModelFreeMethod(std::string method, MethodConfig config) : method_(std::move(method)), config_(std::move(config)) {}

  std::size_t scenes_per_block() const override { return 1; }

  std::vector<Gaussian3> add(std::span<const Measurement> rows) override {
    return run_method(method_, config_, rows, &gating_);
  }

  std::vector<Gaussian3> finish() override { return {}; }

  void log_report() const override {
    if (method_ == "wls") log_gating(method_, config_.wls_gate, gating_);
    if (method_ == "mmt") log_gating(method_, config_.mmt_gate, gating_);
  }

 private:
  std::string method_;
  MethodConfig config_;
  GatingSummary gating_;
};

}  // namespace

std::unique_ptr<BlockMethod> prepare_model_free_method(const std::string& method, const MethodConfig& config) {
  return std::make_unique<ModelFreeMethod>(method, config);
}

}  // namespace stgf::cli
