// SPDX-License-Identifier: Apache-2.0
// The model file reader's fuzz harness. LibTorch 1.13's headers do not compile with clang 14 in C++20,
// so instead of a libFuzzer target this is a mutation loop built with the project's compiler: it
// takes a valid model file and loads ITERATIONS mutated copies (random byte flips, overwritten runs,
// truncations, insertions, and runs copied from elsewhere in the file, 1–8 per copy), checking the
// reader's contract: it returns a model or throws stgf::InputError naming the file; anything else
// (another exception, a crash) is a finding, and the input is kept as mutate-model-finding.pt.
//   fuzz_model_file SEED_MODEL.pt ITERATIONS [RANDOM_SEED]
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "stgf/io/input_error.hpp"
#include "stgf/learn/motion_model.hpp"

namespace {

std::string read_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string mutate(std::string bytes, std::mt19937_64& random) {
  const int edits = 1 + static_cast<int>(random() % 8);
  for (int k = 0; k < edits && !bytes.empty(); ++k) {
    const std::size_t at = random() % bytes.size();
    switch (random() % 5) {
      case 0:  // flip bits of one byte
        bytes[at] = static_cast<char>(bytes[at] ^ static_cast<char>(1 + random() % 255));
        break;
      case 1:  // overwrite a run with random bytes
        for (std::size_t i = at; i < std::min(bytes.size(), at + 1 + random() % 64); ++i) {
          bytes[i] = static_cast<char>(random());
        }
        break;
      case 2:  // truncate
        bytes.resize(at);
        break;
      case 3:  // insert random bytes
        bytes.insert(at, std::string(1 + random() % 16, static_cast<char>(random())));
        break;
      default: {  // copy a run from elsewhere in the file
        const std::size_t from = random() % bytes.size();
        const std::size_t length = std::min({bytes.size() - from, bytes.size() - at, std::size_t{1} + random() % 256});
        bytes.replace(at, length, bytes.substr(from, length));
      }
    }
  }
  return bytes;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fuzz_model_file SEED_MODEL.pt ITERATIONS [RANDOM_SEED]\n");
    return 2;
  }
  const std::string seed = read_file(argv[1]);
  if (seed.empty()) {
    std::fprintf(stderr, "fuzz_model_file: %s is empty or missing\n", argv[1]);
    return 2;
  }
  const long iterations = std::atol(argv[2]);
  std::mt19937_64 random(argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1);
  const std::string path = "/tmp/stgf_fuzz_model_" + std::to_string(::getpid()) + ".pt";
  long loaded = 0, rejected = 0;
  for (long k = 0; k < iterations; ++k) {
    const std::string bytes = mutate(seed, random);
    write_file(path, bytes);
    try {
      stgf::MotionModel::load(path);
      ++loaded;
    } catch (const stgf::InputError& error) {
      if (std::string(error.what()).rfind(path + ": ", 0) != 0) {
        std::fprintf(stderr, "finding: the error does not name the file: %s\n", error.what());
        write_file("mutate-model-finding.pt", bytes);
        return 1;
      }
      ++rejected;
    } catch (const std::exception& error) {
      std::fprintf(stderr, "finding: not an InputError: %s\n", error.what());
      write_file("mutate-model-finding.pt", bytes);
      return 1;
    }
  }
  std::remove(path.c_str());
  std::printf("fuzz_model_file: %ld mutated model files: %ld rejected with an input error, %ld loaded "
              "(mutations outside the checked records), no finding\n",
              iterations, rejected, loaded);
  return 0;
}
