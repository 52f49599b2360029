#include "stgf/io/method_config_file.hpp"

#include <fstream>

#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_method_config("c.yaml", text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(MethodConfigFile, EmptyFileKeepsDefaults) {
  const MethodConfig config = parse_method_config("c.yaml", "# nothing\n");
  EXPECT_DOUBLE_EQ(config.mmt.initial_position_variance, 10.0);
  EXPECT_DOUBLE_EQ(config.mmt.initial_velocity_variance, 1e6);
  EXPECT_DOUBLE_EQ(config.mmt.position_noise_density, 10.0);
  EXPECT_DOUBLE_EQ(config.mmt.velocity_noise_density, 10.0);
}

TEST(MethodConfigFile, ReadsMmtSettings) {
  const MethodConfig config =
      parse_method_config("c.yaml", "mmt:\n  position_noise_density: 0.5\n  velocity_noise_density: 2\n");
  EXPECT_DOUBLE_EQ(config.mmt.position_noise_density, 0.5);
  EXPECT_DOUBLE_EQ(config.mmt.velocity_noise_density, 2.0);
  EXPECT_DOUBLE_EQ(config.mmt.initial_position_variance, 10.0);
}

TEST(MethodConfigFile, ErrorsNameTheLine) {
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: 1\n  velocity_nosie_density: 2\n"),
            "c.yaml:3: unknown setting 'mmt.velocity_nosie_density'");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: fast\n"), "c.yaml:2: mmt.position_noise_density must be a number");
  EXPECT_EQ(error_of("mmt:\n  position_noise_density: -1\n"),
            "c.yaml:2: mmt.position_noise_density must be a finite number > 0");
  EXPECT_EQ(error_of("# c\nkalman:\n  a: 1\n"), "c.yaml:2: unknown section 'kalman' (known: mmt)");
  EXPECT_EQ(error_of("mmt: [1, 2\n"), error_of("mmt: [1, 2\n"));  // deterministic parse errors
  EXPECT_NE(error_of("mmt: [1, 2\n").find("c.yaml:"), std::string::npos);
}

// The shipped, documented config holds exactly the defaults.
TEST(MethodConfigFile, ShippedConfigHoldsTheDefaults) {
  const MethodConfig shipped = read_method_config(STGF_SOURCE_DIR "/config/methods.yaml");
  const MethodConfig defaults;
  EXPECT_EQ(shipped.mmt.initial_position_variance, defaults.mmt.initial_position_variance);
  EXPECT_EQ(shipped.mmt.initial_velocity_variance, defaults.mmt.initial_velocity_variance);
  EXPECT_EQ(shipped.mmt.position_noise_density, defaults.mmt.position_noise_density);
  EXPECT_EQ(shipped.mmt.velocity_noise_density, defaults.mmt.velocity_noise_density);
}

}  // namespace
}  // namespace stgf
