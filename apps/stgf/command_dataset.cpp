// SPDX-License-Identifier: Apache-2.0
// stgf dataset synthetic|mpl|cad|ethucy --out DIR [--seed S] [options of each builder]
//              [--asynchronous [--jitter S]] [--latency S]

#include <chrono>
#include <filesystem>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "input_guard.hpp"
#include "install_layout.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/cad_benchmark.hpp"
#include "stgf/datasets/ethucy_benchmark.hpp"
#include "stgf/datasets/mpl_benchmark.hpp"
#include "stgf/datasets/synthetic.hpp"

namespace stgf::cli {
namespace {

void log_counts(const std::string& out, const Benchmark& benchmark, double seconds) {
  const auto count = [](const BenchmarkSplit& split) { return split.measurements.size(); };
  spdlog::info("wrote {} (train {} / val {} / test {} measurements) in {:.2f} s", out, count(benchmark.train),
               count(benchmark.val), count(benchmark.test), seconds);
}

// Builds the benchmark with `make` and writes it to `out`, timing both.
template <class Make>
void build_and_write(const std::string& out, const Make& make) {
  const auto start = std::chrono::steady_clock::now();
  const Benchmark benchmark = make();
  write_benchmark_folder(out, benchmark);
  log_counts(out, benchmark, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// --asynchronous, --jitter, --latency: the same for every builder (stgf/datasets/view_clocks.hpp).
void add_clock_options(CLI::App& command, ViewClockOptions& clocks) {
  CLI::Option* asynchronous = command.add_flag(
      "--asynchronous", clocks.asynchronous,
      "each view measures on its own clock: a phase in [0, T) per view and scene (T = the frame period) plus a "
      "jitter per message; positions move with their objects, and the truth is given at every measured time");
  command.add_option("--jitter", clocks.jitter_s, "σ of each message's timing jitter (s; needs --asynchronous; below T/10)")
      ->capture_default_str()
      ->needs(asynchronous);
  command
      .add_option("--latency", clocks.latency_s,
                  "messages reach the fuser up to S s after they were measured (uniform): adds the arrival column "
                  "(s; 0 = none)")
      ->capture_default_str();
}

void add_synthetic(CLI::App& dataset) {
  struct Options {
    std::string out;
    SyntheticOptions synthetic;
  };
  auto options = std::make_shared<Options>();
  SyntheticOptions& s = options->synthetic;
  CLI::App* command = dataset.add_subcommand(
      "synthetic", "Simulated objects that turn, stop and avoid each other, seen by views placed around the scene.");
  command->add_option("--out", options->out, "benchmark folder to write (replaced if it is a previous benchmark)")
      ->required();
  command->add_option("--seed", s.seed, "random seed; the same seed gives byte-identical files")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--objects", s.objects, "objects per scene")->capture_default_str()->check(CLI::PositiveNumber);
  command->add_option("--views", s.views, "views per scene")->capture_default_str()->check(CLI::PositiveNumber);
  command->add_option("--steps", s.steps, "steps per scene")->capture_default_str()->check(CLI::Range(2, 1000000));
  command->add_option("--scenes", s.scenes, "scenes in each of train, val and test")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--rate", s.rate_hz, "steps per second (Hz)")->capture_default_str()->check(CLI::PositiveNumber);
  add_clock_options(*command, s.clocks);
  command->callback([options] { build_and_write(options->out, [&] { return make_synthetic_benchmark(options->synthetic); }); });
}

void add_mpl(CLI::App& dataset) {
  struct Options {
    std::string out;
    MplOptions mpl;
  };
  auto options = std::make_shared<Options>();
  MplOptions& m = options->mpl;
  CLI::App* command = dataset.add_subcommand(
      "mpl",
      "PETS 2009 S2L1 pedestrians (real trajectories) seen by its 7 calibrated cameras, with pixel noise\n"
      "back-projected to the ground and a per-camera calibration error that R does not state.");
  command->add_option("--out", options->out, "benchmark folder to write (replaced if it is a previous benchmark)")
      ->required();
  command->add_option("--seed", m.seed, "random seed; the same seed gives byte-identical CSV files")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--source", m.source_directory,
                      "PETS 2009 S2L1 folder (annotation XML + calibration/; default: the shipped one)");
  command->add_option("--train", m.train_instances, "training instances")->capture_default_str();
  command->add_option("--val", m.val_instances, "validation instances")->capture_default_str();
  command->add_option("--test", m.test_instances, "test instances")->capture_default_str();
  command->add_option("--steps", m.steps, "steps per instance (7 Hz)")->capture_default_str();
  command->add_option("--pedestrians", m.pedestrians, "pedestrians per instance")->capture_default_str();
  command->add_option("--views", m.views, "PETS cameras used")->delimiter(',')->capture_default_str();
  command->add_option("--pixel-noise-u", m.pixel_noise_u_px, "σ of the foot point along image rows (px)")
      ->capture_default_str();
  command->add_option("--pixel-noise-v", m.pixel_noise_v_px, "σ of the foot point down image columns (px)")
      ->capture_default_str();
  command->add_option("--height-noise", m.ground_height_noise_m, "σ of the measured height (m)")
      ->capture_default_str();
  command->add_option("--detection-probability", m.detection_probability, "chance a visible person is detected")
      ->capture_default_str();
  command->add_option("--calibration-rotation-deg", m.calibration_rotation_error_deg,
                      "σ per axis of each camera's rotation error (degrees; not in R; 0 = off)")
      ->capture_default_str();
  command->add_option("--calibration-translation-m", m.calibration_translation_error_m,
                      "σ per axis of each camera's position error (m; not in R; 0 = off)")
      ->capture_default_str();
  add_clock_options(*command, m.clocks);
  command->callback([options] {
    if (options->mpl.source_directory.empty()) options->mpl.source_directory = shipped_data_directory() + "/pets2009_s2l1";
    // The folder --out is replaced: the source data may not be in it.
    refuse_outputs_over_inputs("--out", {options->out}, {options->mpl.source_directory});
    build_and_write(options->out, [&] { return make_mpl_benchmark(options->mpl); });
  });
}

void add_cad(CLI::App& dataset) {
  struct Options {
    std::string out;
    CadOptions cad;
  };
  auto options = std::make_shared<Options>();
  CadOptions& c = options->cad;
  CLI::App* command = dataset.add_subcommand(
      "cad",
      "KITTI tracking (real 10 Hz tracks): the ego car and up to three other moving cars act as connected\n"
      "vehicles with range- and field-of-view-limited RGB-D sensors and a GPS pose error that R does not state.");
  command->add_option("--out", options->out, "benchmark folder to write (replaced if it is a previous benchmark)")
      ->required();
  command->add_option("--seed", c.seed, "random seed; the same seed gives byte-identical CSV files")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--source", c.source_directory,
                      "KITTI tracking training folder: label/ oxts/ calib/ (default: $STGF_KITTI_DIR, else "
                      "share/stgf/kitti_tracking; KITTI is not shipped, see data/README.md)");
  command->add_option("--train", c.train_instances, "training instances")->capture_default_str();
  command->add_option("--val", c.val_instances, "validation instances")->capture_default_str();
  command->add_option("--test", c.test_instances, "test instances")->capture_default_str();
  command->add_option("--train-sequences", c.train_sequences, "KITTI sequences of the training split")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--val-sequences", c.val_sequences, "KITTI sequences of the validation split")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--test-sequences", c.test_sequences, "KITTI sequences of the test split")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--steps", c.steps, "steps per instance (10 Hz)")->capture_default_str();
  command->add_option("--objects", c.objects, "tracked objects per instance")->capture_default_str();
  command->add_option("--max-vehicles", c.max_vehicles, "connected vehicles per instance, ego included")
      ->capture_default_str();
  command->add_option("--min-vehicles", c.min_vehicles, "windows with fewer possible vehicles are skipped")
      ->capture_default_str();
  command->add_option("--range", c.max_range_m, "sensor range (m)")->capture_default_str();
  command->add_option("--fov", c.field_of_view_deg, "horizontal field of view (degrees)")->capture_default_str();
  command->add_option("--gps-position-error", c.gps_position_error_m,
                      "σ per horizontal axis of each vehicle's position error (m; not in R; 0 = off)")
      ->capture_default_str();
  command->add_option("--gps-heading-error", c.gps_heading_error_deg,
                      "σ of each vehicle's heading error (degrees; not in R; 0 = off)")
      ->capture_default_str();
  add_clock_options(*command, c.clocks);
  command->callback([options] {
    if (options->cad.source_directory.empty()) options->cad.source_directory = default_kitti_directory();
    if (!std::filesystem::is_directory(options->cad.source_directory)) {
      throw std::invalid_argument("no KITTI tracking folder at " + options->cad.source_directory +
                                  " (KITTI is not shipped with stgf: give its label/, oxts/ and calib/ folders with "
                                  "--source or STGF_KITTI_DIR; data/README.md)");
    }
    // The folder --out is replaced: the source data may not be in it.
    refuse_outputs_over_inputs("--out", {options->out}, {options->cad.source_directory});
    build_and_write(options->out, [&] { return make_cad_benchmark(options->cad); });
  });
}

void add_ethucy(CLI::App& dataset) {
  struct Options {
    std::string out;
    EthUcyOptions ethucy;
  };
  auto options = std::make_shared<Options>();
  EthUcyOptions& e = options->ethucy;
  CLI::App* command = dataset.add_subcommand(
      "ethucy",
      "ETH/UCY pedestrians (real trajectories) seen by simulated cameras around each scene; leave-one-scene-out.");
  command->add_option("--out", options->out, "benchmark folder to write (replaced if it is a previous benchmark)")
      ->required();
  command->add_option("--seed", e.seed, "random seed; the same seed gives byte-identical files")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--source", e.source_directory, "folder with the eight ETH/UCY files (default: the shipped one)");
  command->add_option("--test-scene", e.test_scene, "held-out scene")
      ->capture_default_str()
      ->check(CLI::IsMember({"eth", "hotel", "univ", "zara1", "zara2"}));
  command->add_option("--train", e.train_instances, "training instances")->capture_default_str();
  command->add_option("--val", e.val_instances, "validation instances")->capture_default_str();
  command->add_option("--test", e.test_instances, "test instances (0: every window of the test scene once)")
      ->capture_default_str();
  command->add_option("--steps", e.steps, "steps per instance (0.4 s each)")->capture_default_str();
  command->add_option("--min-objects", e.min_objects, "pedestrians present throughout, at least")->capture_default_str();
  command->add_option("--max-objects", e.max_objects, "pedestrians per instance, at most")->capture_default_str();
  command->add_option("--views", e.views, "cameras per scene")->capture_default_str();
  command->add_option("--registration-bias", e.registration_bias_m,
                      "σ of each camera's registration offset per instance (m; not in R; 0 = off)")
      ->capture_default_str();
  add_clock_options(*command, e.clocks);
  command->callback([options] {
    if (options->ethucy.source_directory.empty()) options->ethucy.source_directory = shipped_data_directory() + "/eth_ucy";
    // The folder --out is replaced: the source data may not be in it.
    refuse_outputs_over_inputs("--out", {options->out}, {options->ethucy.source_directory});
    build_and_write(options->out, [&] { return make_ethucy_benchmark(options->ethucy); });
  });
}

}  // namespace

void add_dataset_command(CLI::App& app) {
  CLI::App* dataset = app.add_subcommand("dataset", "Build a benchmark folder (train/val/test measurements and truth).");
  dataset->require_subcommand(1);
  add_synthetic(*dataset);
  add_mpl(*dataset);
  add_cad(*dataset);
  add_ethucy(*dataset);
}

}  // namespace stgf::cli
