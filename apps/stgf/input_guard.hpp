// SPDX-License-Identifier: Apache-2.0
#pragma once
// Nothing the user gave is ever overwritten: an output path that is, or links to, one of the
// command's input files is a usage error (std::invalid_argument, exit status 2), raised before
// anything is read or written.

#include <string>
#include <vector>

namespace stgf::cli {

// `option` names the output (e.g. "--out"); `inputs` are the input files given (empty entries are
// skipped). Throws std::invalid_argument when `output` exists and is the same file as an input.
void refuse_output_over_input(const std::string& option, const std::string& output,
                              const std::vector<std::string>& inputs);

// For a command that writes (or replaces) whole folders and files: `written` are those paths.
// Throws std::invalid_argument when an input file or folder is one of them or lies inside one
// (links followed), since writing would destroy it.
void refuse_outputs_over_inputs(const std::string& option, const std::vector<std::string>& written,
                                const std::vector<std::string>& inputs);

// For a command that writes files named `prefix`… into `folder`: throws std::invalid_argument when an
// input is such a file (links followed).
void refuse_prefixed_outputs_over_inputs(const std::string& option, const std::string& folder,
                                         const std::string& prefix, const std::vector<std::string>& inputs);

}  // namespace stgf::cli
