// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/estimate_file.hpp"

#include <filesystem>

#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"
#include "stgf/io/scene_order.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

using testing::entries_of;
using testing::file_bytes;
using testing::ScratchDirectory;

TEST(EstimateFile, WrittenFileReadsBackTheSame) {
  Matrix3d covariance;
  covariance << 0.5, 0.1, 0, 0.1, 0.4, 0.05, 0, 0.05, 0.3;
  const std::vector<Estimate> rows = {
      {"s", 0.0, "v1", "o1", Gaussian3::from_covariance(Vector3d(1, 2, 3), covariance)},
      {"s", 0.1, "v2", "o1", Gaussian3::from_covariance(Vector3d(-1.5, 2.25, 0), 2.0 * covariance)}};
  const ScratchDirectory directory;
  write_estimates(directory / "estimates.csv", rows, "wls");
  const EstimateFile file = read_estimates(directory / "estimates.csv");
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

// Row by row, the writer writes write_estimates' bytes, and nothing at all until commit().
TEST(EstimateWriter, WritesTheBytesOfWriteEstimatesOnlyOnCommit) {
  const ScratchDirectory directory;
  const std::vector<Estimate> rows = {
      {"s, quoted", 0.1, "v1", "o1", Gaussian3::from_covariance(Vector3d(1, 2, 3), Matrix3d::Identity())},
      {"s, quoted", 0.2, "v2", "o1", Gaussian3::from_covariance(Vector3d(1e6 / 3, -2, 0.5), 0.01 * Matrix3d::Identity())}};
  write_estimates(directory / "whole.csv", rows, "ours");
  {
    EstimateWriter writer(directory / "rows.csv", "ours");
    for (const Estimate& row : rows) writer.write(row.scene, row.time, row.view, row.object, row.position);
    EXPECT_FALSE(std::filesystem::exists(directory / "rows.csv"));
    writer.commit();
  }
  EXPECT_EQ(file_bytes(directory / "rows.csv"), file_bytes(directory / "whole.csv"));

  const std::string previous = directory.write("kept.csv", "previous\n");
  {
    EstimateWriter writer(previous, "ours");
    writer.write(rows[0].scene, rows[0].time, rows[0].view, rows[0].object, rows[0].position);
  }  // an error before commit()
  EXPECT_EQ(file_bytes(previous), "previous\n");
  EXPECT_EQ(entries_of(directory.path()), (std::vector<std::string>{"kept.csv", "rows.csv", "whole.csv"}));
}

TEST(EstimateSceneReader, ReadsOneSceneAtATimeWithItsMethods) {
  const std::string header = "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method\n";
  EstimateSceneReader reader = EstimateSceneReader::from_text(
      "e.csv", header + "s,0,v,o,1,2,3,1,0,0,1,0,1,a\ns,0,v,o,1,2,3,1,0,0,1,0,1,b\nr,0,v,o,1,2,3,1,0,0,1,0,1,a\n");
  EstimateFile scene;
  ASSERT_TRUE(reader.read(scene));
  EXPECT_EQ(scene.methods, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(scene.lines, (std::vector<int>{2, 3}));
  ASSERT_TRUE(reader.read(scene));
  EXPECT_EQ(scene.methods, std::vector<std::string>{"a"});
  EXPECT_FALSE(reader.read(scene));

  EstimateSceneReader back = EstimateSceneReader::from_text(
      "e.csv", header + "s,0,v,o,1,2,3,1,0,0,1,0,1,a\nr,0,v,o,1,2,3,1,0,0,1,0,1,a\ns,1,v,o,1,2,3,1,0,0,1,0,1,a\n");
  ASSERT_TRUE(back.read(scene));
  EXPECT_THROW(back.read(scene), SceneOrderError);
}

}  // namespace
}  // namespace stgf
