// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test helpers: a zip file of stored records, as LibTorch writes its archives, and a record of an
// existing zip file replaced (its CRC-32 made right), so that tests reach the checks behind the
// archive's own.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace stgf::testing {

inline std::uint32_t crc32_of(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFU;
  for (const char c : bytes) {
    crc ^= static_cast<unsigned char>(c);
    for (int k = 0; k < 8; ++k) crc = (crc & 1U) != 0 ? 0xEDB88320U ^ (crc >> 1) : crc >> 1;
  }
  return crc ^ 0xFFFFFFFFU;
}

inline void put16(std::string& out, std::uint32_t value) {
  out += static_cast<char>(value & 0xFF);
  out += static_cast<char>((value >> 8) & 0xFF);
}
inline void put32(std::string& out, std::uint32_t value) {
  put16(out, value & 0xFFFF);
  put16(out, value >> 16);
}

// A zip file of the records (name, bytes), stored.
inline std::string zip_of(const std::vector<std::pair<std::string, std::string>>& records) {
  std::string out, directory;
  for (const auto& [name, bytes] : records) {
    const auto offset = static_cast<std::uint32_t>(out.size());
    const std::uint32_t crc = crc32_of(bytes);
    const auto size = static_cast<std::uint32_t>(bytes.size());
    put32(out, 0x04034b50U);
    put16(out, 20);  // version needed
    put16(out, 0);   // flags
    put16(out, 0);   // stored
    put32(out, 0);   // time, date
    put32(out, crc);
    put32(out, size);
    put32(out, size);
    put16(out, static_cast<std::uint32_t>(name.size()));
    put16(out, 0);  // extra
    out += name;
    out += bytes;
    put32(directory, 0x02014b50U);
    put16(directory, 20);
    put16(directory, 20);
    put16(directory, 0);
    put16(directory, 0);
    put32(directory, 0);
    put32(directory, crc);
    put32(directory, size);
    put32(directory, size);
    put16(directory, static_cast<std::uint32_t>(name.size()));
    put16(directory, 0);  // extra
    put16(directory, 0);  // comment
    put16(directory, 0);  // disk
    put16(directory, 0);  // internal attributes
    put32(directory, 0);  // external attributes
    put32(directory, offset);
    directory += name;
  }
  const auto directory_offset = static_cast<std::uint32_t>(out.size());
  out += directory;
  put32(out, 0x06054b50U);
  put16(out, 0);
  put16(out, 0);
  put16(out, static_cast<std::uint32_t>(records.size()));
  put16(out, static_cast<std::uint32_t>(records.size()));
  put32(out, static_cast<std::uint32_t>(directory.size()));
  put32(out, directory_offset);
  put16(out, 0);
  return out;
}

// Where the stored record `name` of `zip` is: its central directory entry, its local header, and
// its bytes (start, size).
struct RecordPlace {
  std::size_t directory, local, start, size;
};
inline RecordPlace place_of(const std::string& zip, const std::string& name) {
  const auto u16 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(zip[at]) | static_cast<unsigned char>(zip[at + 1]) << 8);
  };
  const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
  std::size_t end = zip.size() - 22;
  while (u32(end) != 0x06054b50U) --end;
  std::size_t at = u32(end + 16);
  for (std::uint32_t k = 0; k < u16(end + 10); ++k) {
    const std::size_t name_length = u16(at + 28);
    if (zip.compare(at + 46, name_length, name) == 0) {
      const std::size_t local = u32(at + 42);
      return {at, local, local + 30 + u16(local + 26) + u16(local + 28), u32(at + 24)};
    }
    at += 46 + name_length + u16(at + 30) + u16(at + 32);
  }
  throw std::logic_error("no record " + name);
}

// `zip` with the stored record `name` given new bytes of the same size, and its CRC-32 fixed in both
// headers.
inline std::string with_record(std::string zip, const std::string& name, const std::string& bytes) {
  const RecordPlace place = place_of(zip, name);
  if (place.size != bytes.size()) throw std::logic_error("with_record: the record's size differs");
  zip.replace(place.start, bytes.size(), bytes);
  std::string crc;
  put32(crc, crc32_of(bytes));
  zip.replace(place.directory + 16, 4, crc);
  zip.replace(place.local + 14, 4, crc);
  return zip;
}

// The bytes of the stored record `name` of `zip`.
inline std::string record_of(const std::string& zip, const std::string& name) {
  const RecordPlace place = place_of(zip, name);
  return zip.substr(place.start, place.size);
}

}  // namespace stgf::testing
