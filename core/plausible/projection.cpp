#include "core/plausible/projection.hpp"

namespace chainmail {
namespace {

// relative compliance on the diagonal: rows that contradict each other (a ring held by two
// colliders at a corner) get large but finite multipliers
constexpr double kRegularisation = 1e-6;
// solves that may release rows before the last one
constexpr int kReleaseRounds = 4;

}  // namespace

bool Projection::solve(const std::vector<ProjectionRow>& rows, const std::vector<char>& active,
                       const std::vector<double>& inverse_mass, Eigen::VectorXd& mu) {
  const int m = static_cast<int>(rows.size());
  // the pattern depends on the rows' rings only; inactive rows keep their entries as zeros, so
  // releasing a row never changes it
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(m);
  for (size_t r = 0; r < by_ring_.size(); ++r) {
    for (const Entry& i : by_ring_[r]) {
      if (active[i.row]) diagonal[i.row] += inverse_mass[r];  // unit gradients
    }
  }
  entries_.clear();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (int k = 0; k < m; ++k) {
    // a row with no diagonal (released, or on pinned rings only) gets 1: its mu stays 0
    const bool empty = diagonal[k] <= 1e-9;
    entries_.emplace_back(k, k, empty ? 1.0 : (1.0 + kRegularisation) * diagonal[k]);
    if (!empty) rhs[k] = -rows[k].violation;
  }
  for (size_t r = 0; r < by_ring_.size(); ++r) {
    const double w = inverse_mass[r];
    for (const Entry& i : by_ring_[r]) {
      for (const Entry& j : by_ring_[r]) {
        if (i.row == j.row) continue;
        const bool both = active[i.row] && active[j.row];
        const double value = w * i.sign * j.sign * rows[i.row].gradient.dot(rows[j.row].gradient);
        entries_.emplace_back(i.row, j.row, both ? value : 0.0);
      }
    }
  }
  matrix_.resize(m, m);
  matrix_.setFromTriplets(entries_.begin(), entries_.end());
  // a new symbolic analysis only when the rows join other rings than last time
  bool same = static_cast<int>(analysed_.size()) == m;
  for (int k = 0; same && k < m; ++k) same = analysed_[k] == std::make_pair(rows[k].a, rows[k].b);
  if (!same) {
    ldlt_.analyzePattern(matrix_);
    analysed_.resize(m);
    for (int k = 0; k < m; ++k) analysed_[k] = {rows[k].a, rows[k].b};
  }
  ldlt_.factorize(matrix_);
  if (ldlt_.info() != Eigen::Success) {
    analysed_.clear();
    return false;
  }
  mu = ldlt_.solve(rhs);
  return ldlt_.info() == Eigen::Success && mu.allFinite();
}

ProjectionResult Projection::project(const std::vector<ProjectionRow>& rows,
                                     const std::vector<double>& inverse_mass, Positions& position) {
  ProjectionResult result;
  const int m = static_cast<int>(rows.size());
  if (m == 0) {  // nothing to solve, nothing moves (and no pattern to factorise)
    result.solved = true;
    return result;
  }
  by_ring_.resize(inverse_mass.size());
  for (auto& list : by_ring_) list.clear();
  for (int k = 0; k < m; ++k) {
    const ProjectionRow& row = rows[k];
    if (row.a >= 0 && inverse_mass[row.a] > 0.0) by_ring_[row.a].push_back({k, -1.0});
    if (row.b >= 0 && inverse_mass[row.b] > 0.0) by_ring_[row.b].push_back({k, 1.0});
  }
  std::vector<char> active(m, 1);
  Eigen::VectorXd mu;
  // a row may only push (mu <= 0); one at its bound that would pull is released and the rest
  // solved again, kReleaseRounds times at most: the multipliers applied are always those of a
  // solve of exactly the rows applied
  for (int round = 0;; ++round) {
    if (!solve(rows, active, inverse_mass, mu)) return result;
    if (round == kReleaseRounds) break;
    int released = 0;
    for (int k = 0; k < m; ++k) {
      if (active[k] && mu[k] > 0.0 && rows[k].violation <= 0.0) active[k] = 0, ++released;
    }
    result.released += released;
    if (released == 0) break;
  }
  result.shift.assign(m, 0.0);
  for (int k = 0; k < m; ++k) {
    if (!active[k]) continue;
    const ProjectionRow& row = rows[k];
    const Vec3 step = mu[k] * row.gradient;
    if (row.a >= 0) position.col(row.a) -= inverse_mass[row.a] * step;
    if (row.b >= 0) position.col(row.b) += inverse_mass[row.b] * step;
    result.shift[k] = -mu[k];
  }
  result.solved = true;
  return result;
}

}  // namespace chainmail
