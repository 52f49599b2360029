// SPDX-License-Identifier: Apache-2.0
#pragma once
// The ETH and UCY pedestrian files (data/eth_ucy/; their source and terms: data/README.md)
// read with stgf's own code into Recordings, and the table of the standard leave-one-scene-out scenes.
//
// ── File format ──────────────────────────────────────────────────────────────────────────────────
// One sample per line, four fields separated by tabs or spaces (any run of them):
//   frame_id  pedestrian_id  x  y
// frame_id is a video frame index and pedestrian_id a whole number, both possibly written as floats
// ("780.0", "1.0"); x, y are ground-plane positions in metres (each scene has its own origin and
// axes). Samples are taken every `frame_step` = 10 video frames, one every 0.4 s, so
//   frame index f = frame_id / frame_step,   time t = f / 2.5 Hz.
// (biwi_eth.txt renumbers ETH's original step of 6 to 10; the time step is still 0.4 s.) Blank lines
// are skipped. The reader stops with InputError "FILE:LINE: reason" on a line that does not have
// four fields, a field that is not a number or not finite, a frame_id that is not a whole multiple of
// frame_step, a pedestrian id that is not a whole number ≥ 0, or a (frame, pedestrian) pair already
// seen; "FILE: reason" when the file cannot be opened or has no samples. Nothing is dropped.
//
// The Recording holds, for every frame index, each pedestrian present as "<prefix>-<id>" (e.g.
// "eth-17") at (x, y, 0).
//
// ── Scenes (leave-one-scene-out) ─────────────────────────────────────────────────────────────────
// The five standard scenes and their files, as in the splits of Social-GAN (Gupta et al., CVPR 2018,
// `scripts/download_data.sh` datasets) and Trajectron++ (Salzmann et al., ECCV 2020,
// `experiments/pedestrians/raw/<scene>/{train,val,test}`), which most trajectory-prediction work
// reuses (e.g. AgentFormer's `data/ethucy_split.py` lists the same eight files):
//   eth   = biwi_eth.txt                      hotel = biwi_hotel.txt
//   univ  = students001.txt + students003.txt
//   zara1 = crowds_zara01.txt                 zara2 = crowds_zara02.txt
// crowds_zara03.txt and uni_examples.txt are never test files: in those splits they are always part of
// training (and validation), whatever the test scene — even though they show the same places as
// zara1/zara2 and univ.

#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "stgf/datasets/recording.hpp"

namespace stgf {

inline constexpr double kEthUcyRateHz = 2.5;  // annotated samples per second (0.4 s apart)
inline constexpr int kEthUcyFrameStep = 10;   // video frame ids between two samples

// Reads ETH/UCY text from `text`. `file_name` is used only in error messages; the Recording is called
// `recording_name`, its objects "<id_prefix>-<pedestrian id>", its rate kEthUcyRateHz.
Recording parse_eth_ucy(std::istream& text, const std::string& file_name, const std::string& recording_name,
                        const std::string& id_prefix, int frame_step = kEthUcyFrameStep);

// Reads the file at `path`: recording name = the file name without directory and extension
// ("biwi_eth"), id prefix = eth_ucy_short_name of it ("eth").
Recording read_eth_ucy_file(const std::string& path, int frame_step = kEthUcyFrameStep);

// "biwi_eth" → "eth", "crowds_zara01" → "zara01": the recording name without a leading "biwi_" or
// "crowds_"; other names ("students001", "uni_examples") unchanged.
std::string eth_ucy_short_name(std::string_view recording_name);

struct EthUcyScene {
  std::string name;                // "eth", "hotel", "univ", "zara1", "zara2"
  std::vector<std::string> files;  // its files, e.g. {"students001.txt", "students003.txt"}
};

// The five leave-one-out scenes in the order eth, hotel, univ, zara1, zara2.
const std::vector<EthUcyScene>& eth_ucy_scenes();

// Files used for training and validation only: {"crowds_zara03.txt", "uni_examples.txt"}.
const std::vector<std::string>& eth_ucy_training_only_files();

// One file of the folder, read.
struct EthUcyFile {
  std::string file_name;  // e.g. "biwi_eth.txt"
  std::string path;       // as opened (directory + "/" + file_name)
  std::string scene;      // its leave-one-out scene, or "" for a training-only file
  Recording recording;
};

// Reads all eight files from `directory`: the scenes' files in scene order, then the training-only
// files. InputError when one is missing or malformed.
std::vector<EthUcyFile> read_eth_ucy_folder(const std::string& directory);

}  // namespace stgf
