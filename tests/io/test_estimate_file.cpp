// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/estimate_file.hpp"

#include <filesystem>

#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

TEST(EstimateFile, WrittenFileReadsBackTheSame) {
  Matrix3d covariance;
  covariance << 0.5, 0.1, 0, 0.1, 0.4, 0.05, 0, 0.05, 0.3;
  const std::vector<Estimate> rows = {
      {"s", 0.0, "v1", "o1", Gaussian3::from_covariance(Vector3d(1, 2, 3), covariance)},
      {"s", 0.1, "v2", "o1", Gaussian3::from_covariance(Vector3d(-1.5, 2.25, 0), 2.0 * covariance)}};
  const std::string path = (std::filesystem::temp_directory_path() / "stgf_test_estimates.csv").string();
  write_estimates(path, rows, "wls");
  const EstimateFile file = read_estimates(path);
  std::filesystem::remove(path);
  ASSERT_EQ(file.rows.size(), 2u);
  EXPECT_EQ(file.methods, (std::vector<std::string>{"wls", "wls"}));
  EXPECT_EQ(file.lines, (std::vector<int>{2, 3}));
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(file.rows[k].view, rows[k].view);
    EXPECT_LT((file.rows[k].position.mean() - rows[k].position.mean()).norm(), 1e-12);
    EXPECT_LT((file.rows[k].position.covariance() - rows[k].position.covariance()).norm(), 1e-9);
  }
}

TEST(EstimateFile, NeedsTheMethodColumn) {
  try {
    parse_estimates("e.csv", "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz\n");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "e.csv:1: missing column 'method'");
  }
}

TEST(EstimateFile, SameRowFromTwoMethodsIsNoDuplicate) {
  const EstimateFile file = parse_estimates(
      "e.csv",
      "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method\n"
      "s,0,v,o,1,2,3,1,0,0,1,0,1,a\n"
      "s,0,v,o,1,2,3,1,0,0,1,0,1,b\n");
  EXPECT_EQ(file.rows.size(), 2u);
}

}  // namespace
}  // namespace stgf
