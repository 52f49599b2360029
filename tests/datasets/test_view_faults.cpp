// SPDX-License-Identifier: Apache-2.0
// A faulty view made on purpose (datasets/view_faults.hpp): only the chosen view changes, as its kind
// says, the same way for the same seed.

#include <gtest/gtest.h>

#include "stgf/datasets/view_faults.hpp"

namespace stgf {
namespace {

std::vector<Measurement> clean_rows() {
  std::vector<Measurement> rows;
  for (const char* scene : {"s1", "s2"}) {
    for (int k = 0; k < 200; ++k) {
      for (const char* view : {"a", "b"}) {
        rows.push_back(Measurement{scene, 0.1 * k, view, "o",
                                   Gaussian3::from_covariance(Vector3d(k, 0.0, 1.0), 0.04 * Matrix3d::Identity()),
                                   std::nullopt, std::nullopt});
      }
    }
  }
  return rows;
}

TEST(ViewFaults, JumpMovesTheViewFromEachScenesMiddleOn) {
  const std::vector<Measurement> clean = clean_rows();
  std::vector<Measurement> rows = clean;
  const ViewFaultSummary summary = inject_view_fault(rows, ViewFaultOptions{ViewFaultKind::kJump, "b"});
  EXPECT_EQ(summary.scenes, 2u);
  EXPECT_EQ(summary.view_rows, 400u);
  EXPECT_EQ(summary.changed_rows, 2u * 100u);  // t from 9.95 s (the middle of 0 … 19.9 s) on
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Vector3d moved = rows[k].position.mean() - clean[k].position.mean();
    const bool faulty = rows[k].view == "b" && rows[k].time >= 9.95;
    EXPECT_NEAR(moved.norm(), faulty ? 1.0 : 0.0, 1e-9);
    EXPECT_EQ(moved.z(), 0.0);  // horizontal
    EXPECT_EQ(rows[k].position.covariance(), clean[k].position.covariance());
  }
}

TEST(ViewFaults, UnderstatedNoiseDividesTheCovarianceOnly) {
  const std::vector<Measurement> clean = clean_rows();
  std::vector<Measurement> rows = clean;
  inject_view_fault(rows, ViewFaultOptions{ViewFaultKind::kUnderstatedNoise, "a"});
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(rows[k].position.mean(), clean[k].position.mean());
    const double factor = rows[k].view == "a" ? 100.0 : 1.0;
    EXPECT_NEAR(rows[k].position.covariance()(0, 0) * factor, 0.04, 1e-15);
  }
}

TEST(ViewFaults, OutliersAreASeededShareOfTheViewsRowsInTheirRange) {
  const std::vector<Measurement> clean = clean_rows();
  ViewFaultOptions options{ViewFaultKind::kOutliers, "a"};
  options.outlier_fraction = 0.1;
  std::vector<Measurement> rows = clean;
  const ViewFaultSummary summary = inject_view_fault(rows, options);
  EXPECT_GT(summary.changed_rows, 20u);  // about 40 of 400
  EXPECT_LT(summary.changed_rows, 70u);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const double moved = (rows[k].position.mean() - clean[k].position.mean()).norm();
    if (rows[k].view != "a") {
      EXPECT_EQ(moved, 0.0);
    }
    if (moved > 0.0) {
      EXPECT_GE(moved, 5.0 - 1e-9);
      EXPECT_LE(moved, 20.0 + 1e-9);
    }
  }
  std::vector<Measurement> again = clean;
  inject_view_fault(again, options);
  for (std::size_t k = 0; k < rows.size(); ++k) EXPECT_EQ(again[k].position.mean(), rows[k].position.mean());
  options.seed = 2;
  std::vector<Measurement> other = clean;
  EXPECT_NE(inject_view_fault(other, options).changed_rows, 0u);
  bool differs = false;
  for (std::size_t k = 0; k < rows.size(); ++k) differs = differs || other[k].position.mean() != rows[k].position.mean();
  EXPECT_TRUE(differs);
}

TEST(ViewFaults, OptionsOutOfRangeAreRefused) {
  std::vector<Measurement> rows = clean_rows();
  ViewFaultOptions options{ViewFaultKind::kUnderstatedNoise, "a"};
  options.understatement = 1.0;
  EXPECT_THROW(inject_view_fault(rows, options), std::invalid_argument);
  options = ViewFaultOptions{ViewFaultKind::kOutliers, "a"};
  options.outlier_min_m = 30.0;
  EXPECT_THROW(inject_view_fault(rows, options), std::invalid_argument);
  EXPECT_THROW(inject_view_fault(rows, ViewFaultOptions{ViewFaultKind::kJump, ""}), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
