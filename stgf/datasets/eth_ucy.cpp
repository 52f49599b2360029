// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/eth_ucy.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <utility>

#include "stgf/datasets/text_input.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

class LineReader {
 public:
  LineReader(const std::string& file_name, int line) : file_name_(file_name), line_(line) {}

  [[noreturn]] void fail(const std::string& reason) const { throw InputError(file_name_, line_, reason); }

  // The whole field as a finite decimal number.
  double number(std::string_view field, std::string_view what) const {
    const std::optional<double> value = parse_number(field);
    if (!value) fail(fmt::format("{} is not a number: '{}'", what, field));
    if (!std::isfinite(*value)) fail(fmt::format("{} is not finite: '{}'", what, field));
    return *value;
  }

  // The field as a whole number (written as an integer or as a float with no fraction, "780.0").
  long long whole_number(std::string_view field, std::string_view what) const {
    const double value = number(field, what);
    constexpr double kLargest = 9.0e15;  // below 2⁵³: every whole double up to here is exact
    if (value != std::floor(value) || std::abs(value) > kLargest) {
      fail(fmt::format("{} is not a whole number: '{}'", what, field));
    }
    return static_cast<long long>(value);
  }

 private:
  const std::string& file_name_;
  int line_;
};

}  // namespace

Recording parse_eth_ucy(std::istream& text, const std::string& file_name, const std::string& recording_name,
                        const std::string& id_prefix, int frame_step) {
  if (frame_step < 1) throw std::invalid_argument("parse_eth_ucy: frame_step must be at least 1");
  Recording recording{recording_name, kEthUcyRateHz, {}};
  std::map<std::pair<int, long long>, int> first_line;  // (frame index, pedestrian) → line
  std::string line;
  int line_number = 0;
  while (std::getline(text, line)) {
    ++line_number;
    // Fields at runs of spaces and tabs (a trailing '\r' counts as a separator).
    const std::vector<std::string_view> fields = split_fields(line, " \t\r");
    if (fields.empty()) continue;
    const LineReader reader(file_name, line_number);
    if (fields.size() != 4) {
      reader.fail(fmt::format("expected 4 fields (frame pedestrian x y), found {}", fields.size()));
    }
    const long long frame_id = reader.whole_number(fields[0], "frame");
    const long long pedestrian = reader.whole_number(fields[1], "pedestrian id");
    const double x = reader.number(fields[2], "x");
    const double y = reader.number(fields[3], "y");
    if (frame_id % frame_step != 0) {
      reader.fail(fmt::format("frame {} is not a multiple of the frame step {}", frame_id, frame_step));
    }
    const long long frame_index = frame_id / frame_step;
    if (frame_index < -2147483647LL || frame_index > 2147483647LL) {
      reader.fail(fmt::format("frame {} is out of range", frame_id));
    }
    if (pedestrian < 0) reader.fail(fmt::format("pedestrian id {} is negative", pedestrian));
    const int frame = static_cast<int>(frame_index);
    const auto [previous, inserted] = first_line.try_emplace({frame, pedestrian}, line_number);
    if (!inserted) {
      reader.fail(fmt::format("pedestrian {} appears twice in frame {} (first on line {})", pedestrian,
                              frame_id, previous->second));
    }
    recording.frames[frame][fmt::format("{}-{}", id_prefix, pedestrian)] = Vector3d(x, y, 0.0);
  }
  if (text.bad()) throw InputError(file_name, 0, "read error");
  if (recording.frames.empty())
    throw InputError(file_name, 0, "no samples (expected lines: frame pedestrian x y)");
  return recording;
}

std::string eth_ucy_short_name(std::string_view recording_name) {
  for (const std::string_view prefix : {std::string_view("biwi_"), std::string_view("crowds_")}) {
    if (recording_name.substr(0, prefix.size()) == prefix)
      return std::string(recording_name.substr(prefix.size()));
  }
  return std::string(recording_name);
}

Recording read_eth_ucy_file(const std::string& path, int frame_step) {
  std::ifstream in = open_text_file(path);
  const std::string name = std::filesystem::path(path).stem().string();
  return parse_eth_ucy(in, path, name, eth_ucy_short_name(name), frame_step);
}

const std::vector<EthUcyScene>& eth_ucy_scenes() {
  static const std::vector<EthUcyScene> scenes = {
      {"eth", {"biwi_eth.txt"}},
      {"hotel", {"biwi_hotel.txt"}},
      {"univ", {"students001.txt", "students003.txt"}},
      {"zara1", {"crowds_zara01.txt"}},
      {"zara2", {"crowds_zara02.txt"}},
  };
  return scenes;
}

const std::vector<std::string>& eth_ucy_training_only_files() {
  static const std::vector<std::string> files = {"crowds_zara03.txt", "uni_examples.txt"};
  return files;
}

std::vector<EthUcyFile> read_eth_ucy_folder(const std::string& directory) {
  std::vector<EthUcyFile> files;
  const auto read = [&](const std::string& file_name, const std::string& scene) {
    std::string path = (std::filesystem::path(directory) / file_name).string();
    Recording recording = read_eth_ucy_file(path);
    files.push_back({file_name, std::move(path), scene, std::move(recording)});
  };
  for (const EthUcyScene& scene : eth_ucy_scenes()) {
    for (const std::string& file_name : scene.files) read(file_name, scene.name);
  }
  for (const std::string& file_name : eth_ucy_training_only_files()) read(file_name, "");
  return files;
}

}  // namespace stgf
