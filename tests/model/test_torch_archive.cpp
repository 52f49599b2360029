// SPDX-License-Identifier: Apache-2.0
// LibTorch's archive read without LibTorch (model/torch_archive.hpp): hand-built archives with the
// opcodes LibTorch's pickler writes, and each way an archive can be wrong, refused with its reason.

#include "stgf/model/torch_archive.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "model/zip_builder.hpp"

namespace stgf {
namespace {

using ::testing::HasSubstr;
using stgf::testing::zip_of;

// Pickle pieces, protocol 2, as LibTorch writes them.
std::string unicode(const std::string& text) {
  std::string out = "X";
  stgf::testing::put32(out, static_cast<std::uint32_t>(text.size()));
  return out + text;
}
std::string global(const std::string& module, const std::string& name) { return "c" + module + "\n" + name + "\n"; }
std::string small_int(int value) { return std::string("K") + static_cast<char>(value); }
// An archive object: NEWOBJ of a __torch__ Module, BUILD with a dict of `items` (key, value pickles).
std::string module(const std::vector<std::pair<std::string, std::string>>& items) {
  std::string out = global("__torch__", "Module") + ")\x81}(";
  for (const auto& [key, value] : items) out += unicode(key) + value;
  return out + "ub";
}
// A float tensor of `sizes` (row-major strides) on storage `key` of `numel` floats, at `offset`.
std::string tensor(const std::string& key, int numel, int offset, const std::vector<int>& sizes,
                   const std::vector<int>& strides, const std::string& storage_type = "FloatStorage") {
  std::string out = global("torch._utils", "_rebuild_tensor_v2") + "((" + unicode("storage") +
                    global("torch", storage_type) + unicode(key) + unicode("cpu") + small_int(numel) + "tQ" +
                    small_int(offset) + "(";
  for (const int size : sizes) out += small_int(size);
  out += "t(";
  for (const int stride : strides) out += small_int(stride);
  return out + "t\x89" + global("collections", "OrderedDict") + ")Rt" + "R";
}
std::string pickle(const std::string& body) { return "\x80\x02" + body + "."; }
std::string floats(const std::vector<float>& values) {
  std::string out(values.size() * sizeof(float), '\0');
  std::memcpy(out.data(), values.data(), out.size());
  return out;
}

std::string refusal(const std::string& bytes) {
  try {
    TorchArchive::parse(bytes);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no error";
}

TEST(TorchArchive, ReadsValuesTensorsAndNestedArchives) {
  std::string binfloat = "G";
  const double value = 2.5;
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int k = 7; k >= 0; --k) binfloat += static_cast<char>((bits >> (8 * k)) & 0xFF);
  const std::string body = module({{"format", unicode("stgf-motion-model")},
                                   {"version", small_int(2)},
                                   {"negative", std::string("J") + std::string("\xfe\xff\xff\xff", 4)},
                                   {"scale", binfloat},
                                   {"flag", "\x88"},
                                   {"network", module({{"weight", tensor("0", 8, 1, {2, 3}, {3, 1})}})}});
  const std::string bytes =
      zip_of({{"archive/data.pkl", pickle(body)}, {"archive/data/0", floats({9, 1, 2, 3, 4, 5, 6, 9})}});
  const TorchArchive archive = TorchArchive::parse(bytes);
  ASSERT_EQ(archive.entries().size(), 6u);
  EXPECT_EQ(archive.entries()[0].key, "format");  // in the order written
  EXPECT_EQ(std::get<std::string>(*archive.find("format")), "stgf-motion-model");
  EXPECT_EQ(std::get<std::int64_t>(*archive.find("version")), 2);
  EXPECT_EQ(std::get<std::int64_t>(*archive.find("negative")), -2);
  EXPECT_EQ(std::get<double>(*archive.find("scale")), 2.5);
  EXPECT_TRUE(std::get<bool>(*archive.find("flag")));
  const auto& network = std::get<std::shared_ptr<const TorchArchive>>(*archive.find("network"));
  const auto& weight = std::get<ArchiveTensor>(*network->find("weight"));
  EXPECT_EQ(weight.sizes, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(weight.values, (std::vector<float>{1, 2, 3, 4, 5, 6}));  // from offset 1
  EXPECT_EQ(archive.find("missing"), nullptr);
}

// A float16 storage (stgf train --weights float16) is read as the floats its values are exactly:
// normal, subnormal, signed zero, the largest half, infinity.
TEST(TorchArchive, ReadsFloat16StoragesAsTheFloatsTheyAre) {
  const std::vector<std::uint16_t> halves = {0x3C00, 0xC000, 0x3555, 0x0001, 0x03FF, 0x8000, 0x7BFF, 0x7C00};
  const std::vector<float> expected = {1.0F, -2.0F, 0.333251953125F, 5.9604644775390625e-8F,
                                       6.0975551605224609375e-5F, -0.0F, 65504.0F,
                                       std::numeric_limits<float>::infinity()};
  std::string storage(2 * halves.size(), '\0');
  std::memcpy(storage.data(), halves.data(), storage.size());
  const std::string body = module({{"w", tensor("0", 8, 0, {2, 4}, {4, 1}, "HalfStorage")}});
  const TorchArchive archive =
      TorchArchive::parse(zip_of({{"archive/data.pkl", pickle(body)}, {"archive/data/0", storage}}));
  const auto& weight = std::get<ArchiveTensor>(*archive.find("w"));
  ASSERT_EQ(weight.values.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(weight.values[k], expected[k]) << k;
    EXPECT_EQ(std::signbit(weight.values[k]), std::signbit(expected[k])) << k;
  }
  // Its size is counted in halves: 8 of them are 16 bytes, not 32.
  EXPECT_THAT(refusal(zip_of({{"archive/data.pkl", pickle(body)}, {"archive/data/0", storage + storage}})),
              HasSubstr("wrong size"));
}

TEST(TorchArchive, RefusesWhatAModelFileNeverHolds) {
  const std::string storage = floats({1, 2, 3, 4});
  const auto archive_with = [&](const std::string& body) {
    return zip_of({{"archive/data.pkl", pickle(body)}, {"archive/data/0", storage}});
  };
  EXPECT_THAT(refusal("not a zip file at all, just text"), HasSubstr("no zip directory"));
  EXPECT_THAT(refusal(""), HasSubstr("too short for a zip archive"));
  EXPECT_THAT(refusal(zip_of({{"archive/other", "x"}})), HasSubstr("no data.pkl"));
  EXPECT_THAT(refusal(zip_of({{"loose.pkl", "x"}})), HasSubstr("not in a folder"));
  // Nothing is called or imported but what a model file holds.
  EXPECT_THAT(refusal(archive_with(global("os", "system") + unicode("echo hi") + "\x85R")),
              HasSubstr("calls 'os system'"));
  EXPECT_THAT(refusal(archive_with("\x95" + std::string(8, '\0'))), HasSubstr("opcode 0x95"));
  EXPECT_THAT(refusal(archive_with(module({{"t", tensor("0", 4, 0, {2, 2}, {1, 2})}}))), HasSubstr("not contiguous"));
  EXPECT_THAT(refusal(archive_with(module({{"t", tensor("0", 4, 1, {2, 2}, {2, 1})}}))), HasSubstr("outside its storage"));
  EXPECT_THAT(refusal(archive_with(module({{"t", tensor("0", 5, 0, {2, 2}, {2, 1})}}))), HasSubstr("wrong size"));
  EXPECT_THAT(refusal(archive_with(module({{"t", tensor("1", 4, 0, {2, 2}, {2, 1})}}))), HasSubstr("not in the archive"));
  EXPECT_THAT(refusal(archive_with(module({{"t", tensor("0", 4, 0, {2, 2}, {2, 1}, "DoubleStorage")}}))),
              HasSubstr("not as float32 or float16"));
  EXPECT_THAT(refusal(archive_with(module({{"a", small_int(1)}, {"a", small_int(2)}}))), HasSubstr("'a' is there twice"));
  EXPECT_THAT(refusal(archive_with(small_int(1))), HasSubstr("does not hold an archive"));
  EXPECT_THAT(refusal(archive_with("0")), HasSubstr("opcode 0x30"));
  EXPECT_THAT(refusal(archive_with("h\x07")), HasSubstr("memo entry it never wrote"));
  EXPECT_THAT(refusal(archive_with(small_int(1) + std::string("r\xff\xff\xff\xff", 5))), HasSubstr("memo index out of range"));
  EXPECT_THAT(refusal(archive_with(std::string("q\x00", 2))), HasSubstr("reads an empty stack"));
  EXPECT_THAT(refusal(zip_of({{"archive/data.pkl", "\x80\x02" + module({})}})), HasSubstr("ends early"));
  EXPECT_THAT(refusal(archive_with("u")), HasSubstr("no mark"));
  EXPECT_THAT(refusal(archive_with(small_int(1) + small_int(2))), HasSubstr("leaves values on its stack"));
  // The zip's own checks: a stored record that fails its CRC-32, and one cut short.
  std::string damaged = archive_with(module({{"t", tensor("0", 4, 0, {2, 2}, {2, 1})}}));
  damaged[damaged.find(storage) + 1] ^= 0x10;
  EXPECT_THAT(refusal(damaged), HasSubstr("'archive/data/0' fails its CRC-32"));
  const std::string whole = archive_with(module({}));
  for (std::size_t size = 0; size < whole.size(); ++size) {
    EXPECT_NE(refusal(whole.substr(0, size)), "no error") << "cut to " << size << " bytes";
  }
}

// Archives within archives up to a depth, then refused rather than recursed into without end.
TEST(TorchArchive, RefusesArchivesNestedTooDeep) {
  std::string body = module({});
  for (int depth = 0; depth < 40; ++depth) body = module({{"inner", body}});
  EXPECT_THAT(refusal(zip_of({{"archive/data.pkl", pickle(body)}})), HasSubstr("nested too deep"));
}

}  // namespace
}  // namespace stgf
