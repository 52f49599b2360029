// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/general_model.hpp"

#include <string>

namespace stgf {

TrainedMotionModel general_model() {
  return TrainedMotionModel::parse(std::string(general_model_bytes()), kGeneralModelName);
}

}  // namespace stgf
