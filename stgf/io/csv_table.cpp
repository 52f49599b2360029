#include "stgf/io/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

std::string_view trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

// Splits one line into fields; quoted fields may hold commas and "" for a quote.
std::vector<std::string> split_fields(const std::string& path, int line, std::string_view text) {
  std::vector<std::string> fields;
  std::string field;
  std::size_t i = 0;
  while (true) {
    field.clear();
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i < text.size() && text[i] == '"') {
      ++i;
      while (true) {
        if (i >= text.size()) throw InputError(path, line, "unterminated quoted field");
        if (text[i] == '"') {
          if (i + 1 < text.size() && text[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += text[i++];
      }
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      if (i < text.size() && text[i] != ',') {
        throw InputError(path, line, "unexpected text after a quoted field");
      }
    } else {
      const auto comma = text.find(',', i);
      const auto end = comma == std::string_view::npos ? text.size() : comma;
      field = std::string(trimmed(text.substr(i, end - i)));
      i = end;
    }
    fields.push_back(field);
    if (i >= text.size()) break;
    ++i;  // the comma
  }
  return fields;
}

}  // namespace

CsvTable CsvTable::read(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, 0, "cannot open the file");
  std::ostringstream contents;
  contents << file.rdbuf();
  if (file.bad()) throw InputError(path, 0, "cannot read the file");
  return parse(path, contents.str());
}

CsvTable CsvTable::parse(const std::string& path, std::string_view text) {
  CsvTable table;
  table.path_ = path;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  int line = 0;
  std::size_t position = 0;
  bool have_header = false;
  while (position < text.size()) {
    const auto newline = text.find('\n', position);
    std::string_view content = text.substr(position, newline == std::string_view::npos
                                                          ? std::string_view::npos
                                                          : newline - position);
    position = newline == std::string_view::npos ? text.size() : newline + 1;
    ++line;
    if (!content.empty() && content.back() == '\r') content.remove_suffix(1);
    if (trimmed(content).empty()) {
      if (!have_header) throw InputError(path, line, "the header row is empty");
      continue;
    }
    std::vector<std::string> fields = split_fields(path, line, content);
    if (!have_header) {
      for (std::size_t c = 0; c < fields.size(); ++c) {
        if (fields[c].empty()) throw InputError(path, line, "header column " + std::to_string(c + 1) + " has no name");
        for (std::size_t d = 0; d < c; ++d) {
          if (fields[d] == fields[c]) throw InputError(path, line, "column '" + fields[c] + "' appears twice");
        }
      }
      table.header_ = std::move(fields);
      have_header = true;
      continue;
    }
    if (fields.size() != table.header_.size()) {
      throw InputError(path, line, "expected " + std::to_string(table.header_.size()) +
                                       " fields as in the header, found " + std::to_string(fields.size()));
    }
    table.rows_.push_back(Row{line, std::move(fields)});
  }
  if (!have_header) throw InputError(path, 0, "the file is empty (no header row)");
  return table;
}

int CsvTable::column_index(std::string_view name) const {
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == name) return static_cast<int>(c);
  }
  return -1;
}

int CsvTable::require_column(std::string_view name) const {
  const int index = column_index(name);
  if (index < 0) throw InputError(path_, 1, "missing column '" + std::string(name) + "'");
  return index;
}

const std::string& CsvTable::text(const Row& row, int column) const {
  const std::string& field = row.fields[static_cast<std::size_t>(column)];
  if (field.empty()) fail(row, "column '" + header_[static_cast<std::size_t>(column)] + "' is empty");
  return field;
}

double CsvTable::number(const Row& row, int column) const {
  const std::string& field = row.fields[static_cast<std::size_t>(column)];
  const std::string& name = header_[static_cast<std::size_t>(column)];
  if (field.empty()) fail(row, "column '" + name + "' is empty");
  const char* begin = field.data();
  if (*begin == '+') ++begin;  // from_chars does not take a leading plus
  double value = 0.0;
  const auto [end, error] = std::from_chars(begin, field.data() + field.size(), value);
  if (error == std::errc::result_out_of_range) fail(row, "column '" + name + "': '" + field + "' is out of range");
  if (error != std::errc() || end != field.data() + field.size()) {
    fail(row, "column '" + name + "': '" + field + "' is not a number");
  }
  if (!std::isfinite(value)) fail(row, "column '" + name + "': '" + field + "' is not finite");
  return value;
}

Eigen::Vector3d CsvTable::vector3(const Row& row, const int (&columns)[3]) const {
  return {number(row, columns[0]), number(row, columns[1]), number(row, columns[2])};
}

Eigen::Matrix3d CsvTable::symmetric3(const Row& row, const int (&columns)[6]) const {
  const double xx = number(row, columns[0]), xy = number(row, columns[1]), xz = number(row, columns[2]);
  const double yy = number(row, columns[3]), yz = number(row, columns[4]), zz = number(row, columns[5]);
  Eigen::Matrix3d matrix;
  matrix << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return matrix;
}

void CsvTable::fail(const Row& row, const std::string& what) const { throw InputError(path_, row.line, what); }

}  // namespace stgf
