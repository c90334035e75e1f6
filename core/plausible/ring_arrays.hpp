// The per-ring arrays the plausible model's ring passes read and write, and the rings' moves they
// measure for the contact list.
#pragma once

#include <algorithm>
#include <limits>

namespace chainmail {

// the per-ring arrays the passes read and write
struct RingArrays {
  double* position;            // (3 n) m
  double* velocity;            // (3 n) m/s
  double* previous;            // (3 n) m
  double* contact_push;        // (n) m
  const double* inverse_mass;  // (n) 1/kg, 0: pinned
};

// how far rings have moved from an anchor (the positions the contact list was built at): the
// farthest move, squared, and the box of all the moves; as constructed, of no ring (what join
// starts from)
struct RingMoves {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  double farthest2 = 0.0;                  // m^2
  double lo[3] = {kInf, kInf, kInf};       // m
  double hi[3] = {-kInf, -kInf, -kInf};    // m
  void add(double x, double y, double z);  // one more ring's move, m
  void join(const RingMoves& other);       // both sets of rings
};

inline void RingMoves::add(double x, double y, double z) {
  farthest2 = std::max(farthest2, (x * x + y * y) + z * z);  // squaredNorm's order
  const double move[3] = {x, y, z};                          // m
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], move[c]);
    hi[c] = std::max(hi[c], move[c]);
  }
}

inline void RingMoves::join(const RingMoves& other) {
  farthest2 = std::max(farthest2, other.farthest2);
  for (int c = 0; c < 3; ++c) {
    lo[c] = std::min(lo[c], other.lo[c]);
    hi[c] = std::max(hi[c], other.hi[c]);
  }
}

}  // namespace chainmail
