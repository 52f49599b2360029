// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small pieces shared by the readers of source data in this layer: the KITTI and ETH/UCY text files
// (kitti_tracking.cpp, eth_ucy.cpp), the PETS 2009 XML files (xml_file.hpp) and the source files
// that benchmark.json identifies by size and hash (mpl_benchmark.cpp). Problems with a file are
// InputError (stgf/io/input_error.hpp) naming it.

#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace stgf {

// The whole file, byte for byte. InputError(path, 0, "cannot open the file") when it cannot be
// opened, InputError(path, 0, "cannot read the file") when reading it fails.
std::string read_whole_file(const std::string& path);

// `path` opened for reading text; InputError(path, 0, "cannot open the file") when it cannot be.
std::ifstream open_text_file(const std::string& path);

// The fields of `line`: its runs of characters that are not in `separators`, in order.
std::vector<std::string_view> split_fields(std::string_view line, std::string_view separators);

// `text` without the blanks (spaces, tabs, '\n', '\r') at either end.
std::string_view trim_blanks(std::string_view text);

// The number all of `text` spells, read by std::from_chars: no blanks, no leading '+', and "inf"
// and "nan" are numbers. nullopt when it is not one number.
std::optional<double> parse_number(std::string_view text);

// All of `text` as one finite number, a leading '+' allowed (no blanks); nullopt otherwise.
std::optional<double> parse_finite_number(std::string_view text);

// All of `text` as one int, a leading '+' allowed (no blanks); nullopt otherwise or when it does
// not fit.
std::optional<int> parse_integer(std::string_view text);

}  // namespace stgf
