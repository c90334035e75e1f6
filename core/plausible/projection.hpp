// Position constraints solved together (after Goldenthal et al. 2007, fast projection): every
// constraint that is violated or holds at its bound becomes one row of a linear system, the rows
// share one sparse LDLT solve, and the positions move by the mass-weighted correction of all of
// them at once. A Newton step: repeated until the largest violation is below a tolerance, it
// converges in a few steps where Gauss-Seidel sweeps need hundreds (a long hanging chain, a sheet
// over a table edge).
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <utility>
#include <vector>

#include "core/types.hpp"

namespace chainmail {

// one inequality C(x) <= 0 linearised at the current positions: C = violation (m, > 0 violated),
// dC/dx_b = gradient, dC/dx_a = -gradient. a = -1 for a constraint on ring b alone (a collider)
struct ProjectionRow {
  int a = -1;
  int b = -1;
  Vec3 gradient = Vec3::Zero();  // unit
  double violation = 0.0;        // m
};

struct ProjectionResult {
  bool solved = false;        // false: the factorisation failed, nothing moved
  int released = 0;           // rows dropped for pulling instead of pushing
  std::vector<double> shift;  // (rows) m, each row's correction along -gradient (>= 0)
};

// Newton steps on rows; keeps the factorisation's symbolic analysis (ordering, elimination tree)
// and its storage from one call to the next while the rows join the same rings
class Projection {
 public:
  // one Newton step: solves (J W J^T) mu = -C and moves p by W J^T mu. A row at its bound
  // (violation <= 0) whose multiplier would hold its rings together instead of pushing them
  // apart is released and the step solved again without it.
  ProjectionResult project(const std::vector<ProjectionRow>& rows,
                           const std::vector<double>& inverse_mass, Positions& position);

 private:
  bool solve(const std::vector<ProjectionRow>& rows, const std::vector<char>& active,
             const std::vector<double>& inverse_mass, Eigen::VectorXd& mu);

  struct Entry {
    int row;
    double sign;  // +1: the row's gradient acts on this ring, -1: minus it
  };
  std::vector<std::vector<Entry>> by_ring_;    // (n) rows acting on each free ring
  std::vector<std::pair<int, int>> analysed_;  // (rows) the rings of the rows last analysed
  std::vector<Eigen::Triplet<double>> entries_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
};

}  // namespace chainmail
