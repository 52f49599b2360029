// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/torch_archive.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string_view>

namespace stgf {
namespace {

static_assert(std::endian::native == std::endian::little, "tensor records are read as little-endian floats");

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument(why); }

// At most this deep: archives within archives (stgf writes two levels).
constexpr int kMaxDepth = 16;

std::uint32_t crc32(const unsigned char* data, std::size_t size) {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  std::uint32_t crc = 0xFFFFFFFFU;
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xFFU] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFU;
}

// A name for messages: at most 80 characters.
std::string quoted(std::string_view name) {
  return "'" + std::string(name.substr(0, 80)) + (name.size() > 80 ? "...'" : "'");
}

// The zip file's records by name, each checked: inside the file, and, if stored, matching its CRC-32
// (nullopt: a compressed record).
using Records = std::map<std::string, std::optional<std::string_view>, std::less<>>;
Records zip_records(const std::string& bytes) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t size = bytes.size();
  const auto u16 = [&](std::size_t at) { return static_cast<std::uint32_t>(data[at] | data[at + 1] << 8); };
  const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
  if (size < 22) refuse("too short for a zip archive");
  std::size_t end = size - 22;  // the end-of-central-directory record, after at most a 64 KB comment
  while (u32(end) != 0x06054b50U) {
    if (end == 0 || size - end > 22 + 65535) refuse("no zip directory");
    --end;
  }
  const std::size_t entries = u16(end + 10);
  std::size_t at = u32(end + 16);
  if (at == 0xFFFFFFFFU || entries == 0xFFFFU) refuse("a ZIP64 archive (not written by stgf train)");
  Records records;
  for (std::size_t k = 0; k < entries; ++k) {
    if (at + 46 > size || u32(at) != 0x02014b50U) refuse("damaged zip directory");
    const std::uint32_t method = u16(at + 10), crc = u32(at + 16), compressed = u32(at + 20), stored = u32(at + 24);
    const std::size_t name_length = u16(at + 28);
    const std::size_t local = u32(at + 42);
    if (at + 46 + name_length > size) refuse("damaged zip directory");
    const std::string name = bytes.substr(at + 46, name_length);
    if (stored == 0xFFFFFFFFU || local == 0xFFFFFFFFU) refuse("a ZIP64 archive (not written by stgf train)");
    if (local + 30 > size || u32(local) != 0x04034b50U) refuse("record " + quoted(name) + " is not where the directory says");
    const std::size_t start = local + 30 + u16(local + 26) + u16(local + 28);
    if (start > size || compressed > size - start) refuse("record " + quoted(name) + " runs past the end of the file");
    // LibTorch compresses its TorchScript code records, which nothing here reads; the pickle and the
    // tensors are stored.
    if (method != 0 || compressed != stored) {
      records.emplace(name, std::nullopt);
    } else {
      if (crc32(data + start, stored) != crc) refuse("record " + quoted(name) + " fails its CRC-32");
      if (!records.emplace(name, std::string_view(bytes).substr(start, stored)).second) {
        refuse("record " + quoted(name) + " is in the archive twice");
      }
    }
    at += 46 + name_length + u16(at + 30) + u16(at + 32);
  }
  return records;
}

// An IEEE 754 binary16 value as the float it is exactly (every half is a float): sign, 5-bit exponent
// (bias 15), 10-bit fraction; subnormals, infinities and NaN included.
float float_from_half(std::uint16_t bits) {
  const std::uint32_t sign = static_cast<std::uint32_t>(bits & 0x8000U) << 16;
  const std::uint32_t exponent = (bits >> 10) & 0x1FU;
  const std::uint32_t fraction = bits & 0x3FFU;
  float magnitude = 0.0F;
  if (exponent == 0) {
    magnitude = std::ldexp(static_cast<float>(fraction), -24);  // subnormal: fraction · 2⁻²⁴
  } else if (exponent == 31) {
    magnitude = fraction == 0 ? std::numeric_limits<float>::infinity() : std::numeric_limits<float>::quiet_NaN();
  } else {
    magnitude = std::ldexp(static_cast<float>(fraction | 0x400U), static_cast<int>(exponent) - 25);
  }
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(magnitude) | sign);
}

// A value on the pickle machine's stack.
struct Node;
using NodePtr = std::shared_ptr<Node>;
struct Node {
  enum class Kind { kNone, kBool, kInt, kFloat, kString, kTuple, kList, kDict, kGlobal, kStorage, kTensor, kObject };
  Kind kind = Kind::kNone;
  bool boolean = false;
  std::int64_t integer = 0;
  double number = 0.0;
  std::string text;            // a string; a global's "module name"; an object's class; a storage's key
  std::vector<NodePtr> items;  // a tuple's or list's items; a dict's keys and values, alternating;
                               // an object's state (none until BUILD); a tensor's storage
  std::vector<std::int64_t> sizes, strides;  // a tensor's
  bool half = false;                         // a storage of float16 values (else float32)
};

NodePtr make(Node::Kind kind) {
  auto node = std::make_shared<Node>();
  node->kind = kind;
  return node;
}

}  // namespace

// Runs the pickle and turns its result into archives.
class ArchivePickle {
 public:
  ArchivePickle(std::string_view pickle, std::string prefix,
                const Records& records)
      : pickle_(pickle), prefix_(std::move(prefix)), records_(records) {}

  TorchArchive archive() {
    const NodePtr root = run();
    TorchArchive result;
    fill(result, *root, 0);
    return result;
  }

 private:
  std::uint8_t byte() {
    if (at_ >= pickle_.size()) refuse("data.pkl ends early");
    return static_cast<std::uint8_t>(pickle_[at_++]);
  }
  std::uint64_t unsigned_bytes(int count) {
    std::uint64_t value = 0;
    for (int k = 0; k < count; ++k) value |= static_cast<std::uint64_t>(byte()) << (8 * k);
    return value;
  }
  std::string_view bytes(std::uint64_t count) {
    if (count > pickle_.size() - at_) refuse("data.pkl ends early");
    const std::string_view result = pickle_.substr(at_, count);
    at_ += count;
    return result;
  }
  std::string line() {
    const std::size_t end = pickle_.find('\n', at_);
    if (end == std::string_view::npos) refuse("data.pkl ends early");
    std::string result(pickle_.substr(at_, end - at_));
    at_ = end + 1;
    return result;
  }
  NodePtr pop() {
    if (stack_.size() <= (marks_.empty() ? 0 : marks_.back())) refuse("data.pkl pops an empty stack");
    NodePtr node = std::move(stack_.back());
    stack_.pop_back();
    return node;
  }
  NodePtr& top() {
    if (stack_.size() <= (marks_.empty() ? 0 : marks_.back())) refuse("data.pkl reads an empty stack");
    return stack_.back();
  }
  // The items since the last mark, which is removed.
  std::vector<NodePtr> pop_to_mark() {
    if (marks_.empty()) refuse("data.pkl has no mark where it needs one");
    std::vector<NodePtr> items(stack_.begin() + static_cast<std::ptrdiff_t>(marks_.back()), stack_.end());
    stack_.resize(marks_.back());
    marks_.pop_back();
    return items;
  }
  void push_tuple(std::vector<NodePtr> items) {
    NodePtr tuple = make(Node::Kind::kTuple);
    tuple->items = std::move(items);
    stack_.push_back(std::move(tuple));
  }
  void push_int(std::int64_t value) {
    NodePtr node = make(Node::Kind::kInt);
    node->integer = value;
    stack_.push_back(std::move(node));
  }
  void put(std::uint64_t index) {
    if (index > pickle_.size()) refuse("data.pkl has a memo index out of range");
    if (memo_.size() <= index) memo_.resize(index + 1);
    memo_[index] = top();
  }
  void get(std::uint64_t index) {
    if (index >= memo_.size() || !memo_[index]) refuse("data.pkl reads a memo entry it never wrote");
    stack_.push_back(memo_[index]);
  }
  static void add_items(Node& container, std::vector<NodePtr> items, Node::Kind kind, const char* opcode) {
    if (container.kind != kind) refuse(std::string("data.pkl's ") + opcode + " is not on a container of its kind");
    for (NodePtr& item : items) container.items.push_back(std::move(item));
  }

  // (storage, offset, sizes, strides, requires_grad, hooks) → a tensor.
  static NodePtr rebuild_tensor(const Node& arguments) {
    const auto& a = arguments.items;
    if (arguments.kind != Node::Kind::kTuple || a.size() != 6 || a[0]->kind != Node::Kind::kStorage ||
        a[1]->kind != Node::Kind::kInt || a[2]->kind != Node::Kind::kTuple || a[3]->kind != Node::Kind::kTuple) {
      refuse("data.pkl rebuilds a tensor from arguments it cannot be");
    }
    NodePtr tensor = make(Node::Kind::kTensor);
    tensor->items.push_back(a[0]);
    tensor->integer = a[1]->integer;
    for (const auto& [list, into] : {std::pair{&a[2]->items, &tensor->sizes}, std::pair{&a[3]->items, &tensor->strides}}) {
      for (const NodePtr& item : *list) {
        if (item->kind != Node::Kind::kInt) refuse("data.pkl gives a tensor a size or stride that is not an integer");
        into->push_back(item->integer);
      }
    }
    return tensor;
  }

  NodePtr run() {
    for (;;) {
      const std::uint8_t opcode = byte();
      switch (opcode) {
        case 0x80: byte(); break;  // PROTO
        case 'c': {                // GLOBAL
          NodePtr global = make(Node::Kind::kGlobal);
          global->text = line();
          global->text += ' ' + line();
          stack_.push_back(std::move(global));
          break;
        }
        case 'q': put(byte()); break;                   // BINPUT
        case 'r': put(unsigned_bytes(4)); break;        // LONG_BINPUT
        case 'h': get(byte()); break;                   // BINGET
        case 'j': get(unsigned_bytes(4)); break;        // LONG_BINGET
        case '(': marks_.push_back(stack_.size()); break;  // MARK
        case ')': push_tuple({}); break;                // EMPTY_TUPLE
        case 't': push_tuple(pop_to_mark()); break;     // TUPLE
        case 0x85: case 0x86: case 0x87: {              // TUPLE1, TUPLE2, TUPLE3
          std::vector<NodePtr> items(opcode - 0x84u);
          for (auto item = items.rbegin(); item != items.rend(); ++item) *item = pop();
          push_tuple(std::move(items));
          break;
        }
        case '}': stack_.push_back(make(Node::Kind::kDict)); break;  // EMPTY_DICT
        case ']': stack_.push_back(make(Node::Kind::kList)); break;  // EMPTY_LIST
        case 'N': stack_.push_back(make(Node::Kind::kNone)); break;  // NONE
        case 0x88: case 0x89: {                                      // NEWTRUE, NEWFALSE
          NodePtr node = make(Node::Kind::kBool);
          node->boolean = opcode == 0x88;
          stack_.push_back(std::move(node));
          break;
        }
        case 'K': push_int(byte()); break;                                         // BININT1
        case 'M': push_int(static_cast<std::int64_t>(unsigned_bytes(2))); break;  // BININT2
        case 'J': push_int(static_cast<std::int32_t>(unsigned_bytes(4))); break;  // BININT
        case 0x8a: {                                                               // LONG1
          const int count = byte();
          if (count > 8) refuse("data.pkl has an integer wider than 64 bits");
          std::uint64_t value = unsigned_bytes(count);
          if (count > 0 && count < 8 && (value >> (8 * count - 1)) != 0) value |= ~std::uint64_t{0} << (8 * count);
          push_int(static_cast<std::int64_t>(value));
          break;
        }
        case 'G': {  // BINFLOAT, big-endian
          std::uint64_t bits = 0;
          for (int k = 0; k < 8; ++k) bits = bits << 8 | byte();
          NodePtr node = make(Node::Kind::kFloat);
          std::memcpy(&node->number, &bits, sizeof bits);
          stack_.push_back(std::move(node));
          break;
        }
        case 'X': case 0x8c: {  // BINUNICODE, SHORT_BINUNICODE
          const std::uint64_t length = opcode == 'X' ? unsigned_bytes(4) : byte();
          NodePtr node = make(Node::Kind::kString);
          node->text = bytes(length);
          stack_.push_back(std::move(node));
          break;
        }
        case 'Q': {  // BINPERSID: ("storage", type, key, device, size)
          const NodePtr id = pop();
          const auto& a = id->items;
          if (id->kind != Node::Kind::kTuple || a.size() != 5 || a[0]->kind != Node::Kind::kString ||
              a[0]->text != "storage" || a[1]->kind != Node::Kind::kGlobal || a[2]->kind != Node::Kind::kString ||
              a[4]->kind != Node::Kind::kInt) {
            refuse("data.pkl has a persistent id that is not a tensor storage");
          }
          if (a[1]->text != "torch FloatStorage" && a[1]->text != "torch HalfStorage") {
            refuse("a tensor is stored as " + quoted(a[1]->text) + ", not as float32 or float16");
          }
          NodePtr storage = make(Node::Kind::kStorage);
          storage->half = a[1]->text == "torch HalfStorage";
          storage->text = a[2]->text;
          storage->integer = a[4]->integer;
          stack_.push_back(std::move(storage));
          break;
        }
        case 'R': {  // REDUCE
          const NodePtr arguments = pop();
          const NodePtr callable = pop();
          if (callable->kind != Node::Kind::kGlobal) refuse("data.pkl calls something that is not a name");
          if (callable->text == "torch._utils _rebuild_tensor_v2") {
            stack_.push_back(rebuild_tensor(*arguments));
          } else if (callable->text == "collections OrderedDict" && arguments->kind == Node::Kind::kTuple &&
                     arguments->items.empty()) {
            stack_.push_back(make(Node::Kind::kDict));
          } else {
            refuse("data.pkl calls " + quoted(callable->text) + ", which a model file never does");
          }
          break;
        }
        case 0x81: {  // NEWOBJ
          const NodePtr arguments = pop();
          const NodePtr type = pop();
          if (type->kind != Node::Kind::kGlobal || type->text.rfind("__torch__", 0) != 0 ||
              !type->text.ends_with(" Module") || arguments->kind != Node::Kind::kTuple || !arguments->items.empty()) {
            refuse("data.pkl makes an object that is not an archive");
          }
          NodePtr object = make(Node::Kind::kObject);
          object->text = type->text;
          stack_.push_back(std::move(object));
          break;
        }
        case 's': {  // SETITEM
          NodePtr value = pop();
          NodePtr key = pop();
          add_items(*top(), {std::move(key), std::move(value)}, Node::Kind::kDict, "SETITEM");
          break;
        }
        case 'u': {  // SETITEMS
          std::vector<NodePtr> items = pop_to_mark();
          if (items.size() % 2 != 0) refuse("data.pkl's SETITEMS has a key without a value");
          add_items(*top(), std::move(items), Node::Kind::kDict, "SETITEMS");
          break;
        }
        case 'a': add_items(*top(), {pop()}, Node::Kind::kList, "APPEND"); break;  // APPEND
        case 'e': add_items(*top(), pop_to_mark(), Node::Kind::kList, "APPENDS"); break;  // APPENDS
        case 'b': {  // BUILD
          NodePtr state = pop();
          Node& object = *top();
          if (object.kind != Node::Kind::kObject || !object.items.empty()) refuse("data.pkl builds something that is not a new archive");
          object.items.push_back(std::move(state));
          break;
        }
        case '.': {  // STOP
          NodePtr result = pop();
          if (!stack_.empty() || !marks_.empty()) refuse("data.pkl leaves values on its stack");
          return result;
        }
        default: {
          static const char* const hex = "0123456789abcdef";
          refuse(std::string("data.pkl has opcode 0x") + hex[opcode >> 4] + hex[opcode & 15] + ", which a model file never has");
        }
      }
    }
  }

  ArchiveTensor tensor(const Node& node) const {
    const Node& storage = *node.items.at(0);
    const auto found = records_.find(prefix_ + "/data/" + storage.text);
    if (found == records_.end()) refuse("tensor storage " + quoted(storage.text) + " is not in the archive");
    if (!found->second) refuse("tensor storage " + quoted(storage.text) + " is compressed (not written by stgf train)");
    const std::string_view record = *found->second;
    const std::int64_t element_size = storage.half ? 2 : 4;
    if (storage.integer < 0 ||
        record.size() != static_cast<std::uint64_t>(storage.integer) * static_cast<std::uint64_t>(element_size)) {
      refuse("tensor storage " + quoted(storage.text) + " has the wrong size");
    }
    if (node.sizes.size() != node.strides.size()) refuse("a tensor has as many strides as sizes");
    ArchiveTensor result{node.sizes, {}};
    // Contiguous (row-major) strides, every size ≥ 0, and the values inside the storage.
    std::int64_t count = 1;
    for (std::size_t d = node.sizes.size(); d-- > 0;) {
      const std::int64_t size = node.sizes[d];
      if (size < 0 || size > std::numeric_limits<std::int32_t>::max()) refuse("a tensor has a size out of range");
      if (size > 1 && node.strides[d] != count) refuse("a tensor is not contiguous");
      count *= size;
      if (count > std::numeric_limits<std::int32_t>::max()) refuse("a tensor is too large");
    }
    if (node.integer < 0 || node.integer > storage.integer || count > storage.integer - node.integer) {
      refuse("a tensor lies outside its storage");
    }
    result.values.resize(static_cast<std::size_t>(count));
    const char* first = record.data() + node.integer * element_size;
    if (storage.half) {
      for (std::size_t k = 0; k < result.values.size(); ++k) {
        std::uint16_t bits = 0;
        std::memcpy(&bits, first + 2 * k, 2);
        result.values[k] = float_from_half(bits);
      }
    } else {
      std::memcpy(result.values.data(), first, result.values.size() * sizeof(float));
    }
    return result;
  }

  void fill(TorchArchive& archive, const Node& object, int depth) const {
    if (depth > kMaxDepth) refuse("archives nested too deep");
    if (object.kind != Node::Kind::kObject || object.items.size() != 1 || object.items[0]->kind != Node::Kind::kDict) {
      refuse("data.pkl does not hold an archive");
    }
    const std::vector<NodePtr>& items = object.items[0]->items;
    std::set<std::string_view> keys;
    for (std::size_t k = 0; k + 1 < items.size(); k += 2) {
      if (items[k]->kind != Node::Kind::kString) refuse("an archive has a key that is not a string");
      const std::string& key = items[k]->text;
      const Node& node = *items[k + 1];
      TorchArchive::Value value;
      switch (node.kind) {
        case Node::Kind::kNone: break;
        case Node::Kind::kBool: value = node.boolean; break;
        case Node::Kind::kInt: value = node.integer; break;
        case Node::Kind::kFloat: value = node.number; break;
        case Node::Kind::kString: value = node.text; break;
        case Node::Kind::kTensor: value = tensor(node); break;
        case Node::Kind::kObject: {
          auto nested = std::make_shared<TorchArchive>();
          fill(*nested, node, depth + 1);
          value = std::shared_ptr<const TorchArchive>(std::move(nested));
          break;
        }
        default: refuse("archive value " + quoted(key) + " is of a kind a model file never holds");
      }
      if (!keys.insert(key).second) refuse("archive value " + quoted(key) + " is there twice");
      archive.entries_.push_back({key, std::move(value)});
    }
  }

  std::string_view pickle_;
  std::size_t at_ = 0;
  std::string prefix_;
  const Records& records_;
  std::vector<NodePtr> stack_;
  std::vector<std::size_t> marks_;
  std::vector<NodePtr> memo_;
};

TorchArchive TorchArchive::parse(const std::string& bytes) {
  const auto records = zip_records(bytes);
  if (records.empty()) refuse("an empty zip archive");
  // Every record is under one folder, named by the first.
  const std::string& first = records.begin()->first;
  const std::size_t slash = first.find('/');
  if (slash == std::string::npos) refuse("the archive's records are not in a folder");
  const std::string prefix = first.substr(0, slash);
  const auto pickle = records.find(prefix + "/data.pkl");
  if (pickle == records.end()) refuse("the archive has no data.pkl");
  if (!pickle->second) refuse("data.pkl is compressed (not written by stgf train)");
  return ArchivePickle(*pickle->second, prefix, records).archive();
}

const TorchArchive::Value* TorchArchive::find(const std::string& key) const {
  for (const Entry& entry : entries_) {
    if (entry.key == key) return &entry.value;
  }
  return nullptr;
}

}  // namespace stgf
