// The Newton step on position constraints: the rows applied reach their bounds together (to first
// order), and a step with nothing to solve moves nothing.
#include <gtest/gtest.h>

#include <vector>

#include "core/plausible/projection.hpp"

namespace chainmail {
namespace {

// each applied row's linearised violation after the step: violation + gradient . (db - da), m
std::vector<double> linearised_after(const std::vector<ProjectionRow>& rows,
                                     const Positions& before, const Positions& after) {
  std::vector<double> left;
  for (const ProjectionRow& row : rows) {
    const Vec3 da = row.a >= 0 ? Vec3(after.col(row.a) - before.col(row.a)) : Vec3::Zero();
    const Vec3 db = after.col(row.b) - before.col(row.b);
    left.push_back(row.violation + row.gradient.dot(db - da));
  }
  return left;
}

TEST(Projection, RowsLeftAfterTheLastReleaseAreSolvedWithoutTheReleasedOnes) {
  // seven rings (the first pinned) and seven rows, three at or inside their bounds, whose
  // multipliers release six rows over five solves: the multipliers applied must be those of a
  // solve without every row released (the last release round's too)
  Positions x(3, 7);
  x << -0.9518, 0.5936, -0.5164, 0.5292, 0.2997, 0.7137, -0.3113,  //
      0.0370, 0.9819, 0.4986, -0.5958, 0.0632, 0.1055, -0.1299,    //
      0.9295, 0.8681, 0.7861, 0.4768, 0.7450, 0.1920, 0.7947;
  const std::vector<double> inverse_mass = {0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  const int pairs[7][2] = {{0, 1}, {1, 6}, {1, 4}, {1, 2}, {2, 3}, {1, 5}, {5, 6}};
  const double violation[7] = {-0.0359, -0.0453, 0.0, 0.0, 0.0, 0.0354, -0.0947};
  std::vector<ProjectionRow> rows;
  for (int k = 0; k < 7; ++k) {
    ProjectionRow row;
    row.a = pairs[k][0];
    row.b = pairs[k][1];
    row.gradient = (x.col(row.b) - x.col(row.a)).normalized();
    row.violation = violation[k];
    rows.push_back(row);
  }
  Positions after = x;
  Projection projection;
  const ProjectionResult result = projection.project(rows, inverse_mass, after);
  ASSERT_TRUE(result.solved);
  EXPECT_GE(result.released, 5);  // the case exercises the last release round
  const std::vector<double> left = linearised_after(rows, x, after);
  int applied = 0;
  for (size_t k = 0; k < rows.size(); ++k) {
    EXPECT_GE(result.shift[k], 0.0) << "row " << k;  // rows only push
    if (result.shift[k] == 0.0) continue;
    ++applied;
    EXPECT_NEAR(left[k], 0.0, 1e-7) << "row " << k;  // at its bound, to first order
  }
  EXPECT_GE(applied, 1);
  EXPECT_TRUE(after.col(0).isApprox(x.col(0)));  // pinned
}

TEST(Projection, NoRowsIsSolvedAndMovesNothing) {
  Positions x = Positions::Random(3, 4);
  const Positions before = x;
  Projection projection;
  const ProjectionResult result = projection.project({}, {1.0, 1.0, 1.0, 1.0}, x);
  EXPECT_TRUE(result.solved);
  EXPECT_TRUE(result.shift.empty());
  EXPECT_EQ(x, before);
}

}  // namespace
}  // namespace chainmail
