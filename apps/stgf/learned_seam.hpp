// SPDX-License-Identifier: Apache-2.0
#pragma once
// The seam between the CLI's two executables (method names: stgf/methods/registry.hpp):
//
//   stgf           everything that needs no LibTorch: run with every method (a trained model is read
//                  and run without LibTorch: stgf/model/trained_motion_model.hpp), eval, plot,
//                  dataset — so that none of them pays LibTorch's start-up (0.8 s and 165 MB, measured);
//   stgf-learned   the same CLI with LibTorch linked in, for training (train, reproduce). stgf hands
//                  its whole command line over to it (exec) when one of those is asked for, so a user
//                  only ever types `stgf`.

#include <memory>
#include <string>

#include "block_method.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf::cli {

// The methods by name: all_method_names() and is_learned_method() of stgf/methods/registry.hpp.

// A learned method with its model loaded and checked, ready to be given the file block by block
// (block_method.hpp). Loads the model (std::invalid_argument naming the file when it is missing or
// trained for another method). method_runner.cpp.
std::unique_ptr<BlockMethod> prepare_learned_method(const std::string& method, const MethodConfig& config,
                                                    const std::string& model_path);

// `--portable` (train, reproduce): the same model bytes on every x86-64 machine. LibTorch picks its
// CPU kernels, and OpenBLAS its matrix-product kernels, by the machine's vector units (AVX2, AVX-512),
// and their sums round differently: trained on two machines with the same seed, a model's weights
// differ at float rounding. The flag pins both to kernels every x86-64 machine runs
// (ATEN_CPU_CAPABILITY=default, OPENBLAS_CORETYPE=Prescott); training takes about twice as long
// (bench/README.md, "Threads"). Both variables are read when the libraries load, so stgf sets them
// before it starts stgf-learned, and stgf-learned started without them starts itself again with them.
inline constexpr const char* kPortableFlag = "--portable";
inline constexpr const char* kPortableFlagHelp =
    "the same model bytes on every x86-64 machine: LibTorch's and OpenBLAS's generic kernels instead of "
    "those of this machine's vector units (training about 2x slower)";
// In stgf-learned, for a command given --portable: returns when the kernels are pinned, else starts
// this executable again on the same command line with them pinned (std::runtime_error if it cannot).
void ensure_portable_kernels();

// main() keeps the command line so that it can be handed over whole.
void remember_command_line(int argc, char** argv);
// Replaces this process with stgf-learned run on the same command line; std::runtime_error when
// stgf-learned is missing (an installation built without LibTorch) or cannot be started.
[[noreturn]] void hand_over_to_learned_cli(const std::string& what);

}  // namespace stgf::cli
