// SPDX-License-Identifier: Apache-2.0
#pragma once
// The archives LibTorch's torch::serialize::OutputArchive writes (a model file, design.md §3.6), read
// without LibTorch, so that running Φ needs none of it (trained_motion_model.hpp).
//
// Such an archive is a zip file of uncompressed records under one folder (`archive/` when written
// through a stream): `data.pkl`, a Python pickle (protocol 2) of the archive's values, and `data/K`,
// the raw bytes of storage K of the tensors it holds. The pickle is read by a small stack machine that
// knows the opcodes LibTorch's pickler writes, and the objects it names:
//   __torch__.… Module        an archive (or a nested archive: OutputArchive::write(key, archive))
//                             whose BUILD state is a dict of its values by key
//   torch._utils _rebuild_tensor_v2(storage, offset, sizes, strides, requires_grad, hooks)   a tensor
//   torch FloatStorage / HalfStorage (a persistent id: "storage", type, key, device, size)  its storage
//                             of float32 / float16 values (a model stored with `stgf train
//                             --weights float16`); float16 values are read as the floats they are
//   collections OrderedDict() an empty dict (the tensor's backward hooks)
// Anything else — another opcode, a ZIP64 archive, a record outside the file, a stored record failing
// its CRC-32, a compressed pickle or tensor (LibTorch compresses only its TorchScript code, which is
// not read), a tensor that is not float32 or float16, contiguous and inside its storage — is refused with the
// reason (std::invalid_argument), never read past. Nothing is executed: the names are matched, not
// imported.

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace stgf {

// A tensor, its values as float32 in row-major order.
struct ArchiveTensor {
  std::vector<std::int64_t> sizes;
  std::vector<float> values;
};

// An archive's values by key, in the order they were written; nested archives are archives too.
class TorchArchive {
 public:
  // Throws std::invalid_argument with the reason when `bytes` is not such an archive.
  static TorchArchive parse(const std::string& bytes);

  using Value = std::variant<std::monostate, bool, std::int64_t, double, std::string, ArchiveTensor,
                             std::shared_ptr<const TorchArchive>>;
  struct Entry {
    std::string key;
    Value value;
  };
  const std::vector<Entry>& entries() const { return entries_; }
  // The value of `key`, or nullptr.
  const Value* find(const std::string& key) const;

 private:
  friend class ArchivePickle;
  std::vector<Entry> entries_;
};

}  // namespace stgf
