// stgf dataset synthetic --out DIR [--seed S] [--objects N] [--views N] [--steps N] [--scenes N] [--rate HZ]

#include <chrono>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/synthetic.hpp"

namespace stgf::cli {
namespace {

struct SyntheticCommandOptions {
  std::string out;
  SyntheticOptions synthetic;
};

void log_counts(const std::string& out, const Benchmark& benchmark, double seconds) {
  const auto count = [](const BenchmarkSplit& split) { return split.measurements.size(); };
  spdlog::info("wrote {} (train {} / val {} / test {} measurements) in {:.2f} s", out, count(benchmark.train),
               count(benchmark.val), count(benchmark.test), seconds);
}

void make_synthetic(const SyntheticCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Benchmark benchmark = make_synthetic_benchmark(options.synthetic);
  write_benchmark_folder(options.out, benchmark);
  log_counts(options.out, benchmark,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

void add_dataset_command(CLI::App& app) {
  CLI::App* dataset = app.add_subcommand("dataset", "Build a benchmark folder (train/val/test measurements and truth).");
  dataset->require_subcommand(1);

  auto options = std::make_shared<SyntheticCommandOptions>();
  SyntheticOptions& s = options->synthetic;
  CLI::App* synthetic = dataset->add_subcommand(
      "synthetic", "Simulated objects that turn, stop and avoid each other, seen by views placed around the scene.");
  synthetic->add_option("--out", options->out, "benchmark folder to write (replaced if it is a previous benchmark)")
      ->required();
  synthetic->add_option("--seed", s.seed, "random seed; the same seed gives byte-identical files")
      ->capture_default_str();
  synthetic->add_option("--objects", s.objects, "objects per scene")->capture_default_str()->check(CLI::PositiveNumber);
  synthetic->add_option("--views", s.views, "views per scene")->capture_default_str()->check(CLI::PositiveNumber);
  synthetic->add_option("--steps", s.steps, "steps per scene")->capture_default_str()->check(CLI::Range(2, 1000000));
  synthetic->add_option("--scenes", s.scenes, "scenes in each of train, val and test")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  synthetic->add_option("--rate", s.rate_hz, "steps per second (Hz)")->capture_default_str()->check(CLI::PositiveNumber);
  synthetic->callback([options] { make_synthetic(*options); });
}

}  // namespace stgf::cli
