// SPDX-License-Identifier: Apache-2.0
#pragma once
// A method as `stgf run` drives it (DESIGN §3.8): it is given the measurements file a block of whole
// scenes at a time, in file order, and gives back one estimate per row, in file order, so that memory
// holds a block, not the file. Each method takes the blocks that give it the estimates of one run over
// the whole file, bit for bit (scenes_per_block()).

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/records.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf::cli {

class BlockMethod {
 public:
  virtual ~BlockMethod() = default;
  // The scenes of a block: kScenesPerFilterBlock for ours and ours-l (filter_runner.hpp); one for the
  // others (sttp continues its passes across blocks). Every method gives any blocks of whole scenes
  // the same estimates; the block bounds what memory holds.
  virtual std::size_t scenes_per_block() const = 0;
  // Takes the next block's rows; returns the estimates now complete, in file order, following those
  // returned before: all of the block's, but for sttp, whose last forward pass may wait for later
  // blocks. A late row under `late_measurements: stop` throws LateMeasurementError with the row's
  // index in `rows`.
  virtual std::vector<Gaussian3> add(std::span<const Measurement> rows) = 0;
  // The estimates of every row not returned yet.
  virtual std::vector<Gaussian3> finish() = 0;
  // Logs what the whole run did that the user should know: the gate, restarted tracks, late rows.
  virtual void log_report() const = 0;
};

// aom, wls or mmt (the methods `stgf` runs without LibTorch).
std::unique_ptr<BlockMethod> prepare_model_free_method(const std::string& method, const MethodConfig& config);

}  // namespace stgf::cli
