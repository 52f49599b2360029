// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the CLI finds what it ships with: relative to its own executable, never a path of the
// machine that built it. The build tree mirrors the installed layout:
//
//   installed                              build tree
//   PREFIX/bin/stgf                        build/stgf
//   PREFIX/libexec/stgf/stgf-learned       build/libexec/stgf/stgf-learned
//   PREFIX/share/stgf/data/                build/share/stgf/data -> the source tree's data/
//   PREFIX/share/stgf/kitti_tracking/      build/share/stgf/kitti_tracking -> -DSTGF_KITTI_DIR (if given)
//
// `share/stgf` is looked for beside the executable and up to three directories above it. The
// environment variables STGF_DATA_DIR (the folder holding pets2009_s2l1/ and eth_ucy/) and
// STGF_KITTI_DIR (a KITTI tracking training folder: label/ oxts/ calib/) override.

#include <string>

namespace stgf::cli {

// The directory of the running executable (/proc/self/exe).
std::string executable_directory();

// The shipped data folder, or std::runtime_error saying where it was looked for.
std::string shipped_data_directory();

// The KITTI tracking folder the cad benchmark reads by default (KITTI is not redistributed with
// stgf: set STGF_KITTI_DIR, give --source, or put it at share/stgf/kitti_tracking). Returns the
// path even when it does not exist; the benchmark reports a missing folder.
std::string default_kitti_directory();

// The CLI's LibTorch half (stgf-learned), or "" when this installation has none.
std::string learned_cli_path();

}  // namespace stgf::cli
