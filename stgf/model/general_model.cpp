// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/general_model.hpp"

#include <stdexcept>
#include <string>

namespace stgf {

TrainedMotionModel general_model() {
  if (general_model_bytes().empty()) {
    throw std::invalid_argument("this stgf was built without its general model (-DSTGF_GENERAL_MODEL=OFF): "
                                "give a model file (stgf train)");
  }
  return TrainedMotionModel::parse(std::string(general_model_bytes()), kGeneralModelName);
}

}  // namespace stgf
