// One pair or one attachment of the plausible model's sweeps, projected on the positions as a
// plain array (3 n, m): the coloured sweep (core/plausible/plausible_solve.cpp) and the banded one
// (core/plausible/plausible_bands.cpp) solve each item with these, so they give the same bits. A
// plain pointer also spares the loop a reload of the positions' own pointer after every write.
#pragma once

#include <cstddef>

#include "core/plausible/constraints.hpp"
#include "core/plausible/pin_attachments.hpp"
#include "core/plausible/sweep_records.hpp"

namespace chainmail {

inline Eigen::Map<Vec3> ring_position(double* x, int ring) {
  return Eigen::Map<Vec3>(x + 3 * static_cast<std::ptrdiff_t>(ring));
}

// an edge or diagonal bound; its violation, m (0: satisfied, nothing written). A pin is never
// written (its correction is zero, and another thread may be reading it for an attachment)
inline double sweep_pair(double* x, const double* w, const EdgeConstraint& e) {
  Vec3 corr0, corr1;
  const double violation =
      solve_edge_constraint(ring_position(x, e.a), w[e.a], ring_position(x, e.b), w[e.b],
                            e.min_length, e.max_length, corr0, corr1);
  if (violation == 0.0) return 0.0;
  if (w[e.a] != 0.0) ring_position(x, e.a) += corr0;
  if (w[e.b] != 0.0) ring_position(x, e.b) += corr1;
  return violation;
}

// a long-range attachment (it moves only its ring); its violation, m (<= 0: none, nothing written)
inline double sweep_attachment(double* x, const PinAttachment& a) {
  Vec3 corr;
  const double violation = solve_attachment_constraint(
      ring_position(x, a.ring), ring_position(x, a.pin), a.max_distance, corr);
  if (violation > 0.0) ring_position(x, a.ring) += corr;
  return violation;
}

}  // namespace chainmail
