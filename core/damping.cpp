#include "core/damping.hpp"
#include "core/parallel.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace chainmail {
namespace {

// solves inertia * omega = momentum on the subspace where the inertia is not (nearly) singular
Vec3 pseudo_solve(const Mat3& inertia, const Vec3& momentum) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(inertia);
  const Vec3 moments = eigen.eigenvalues();
  const double floor = 1e-9 * moments.maxCoeff();
  Vec3 local = eigen.eigenvectors().transpose() * momentum;
  for (int k = 0; k < 3; ++k) local[k] = moments[k] > floor ? local[k] / moments[k] : 0.0;
  return eigen.eigenvectors() * local;
}

}  // namespace

RigidFreedom rigid_freedom(const Positions& position, const MassView& inverse_mass) {
  RigidFreedom freedom;
  const int n = static_cast<int>(position.cols());
  int pins = 0;
  Vec3 mean = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    if (inverse_mass[i] == 0.0) mean += position.col(i), ++pins;
  }
  if (pins == 0) return freedom;
  mean /= pins;
  Mat3 spread = Mat3::Zero();  // m^2, second moment of the pins about their mean
  for (int i = 0; i < n; ++i) {
    if (inverse_mass[i] != 0.0) continue;
    const Vec3 r = position.col(i) - mean;
    spread += r * r.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(spread);
  const Vec3 extent = eigen.eigenvalues();  // ascending
  freedom.point = mean;
  // pins within 1e-6 of their largest extent of a line (or a point) count as on it
  const double scale = std::max(extent[2], 0.0);
  if (scale <= 1e-24) {
    freedom.kind = RigidFreedom::Kind::about_point;
  } else if (extent[1] <= 1e-12 * scale) {
    freedom.kind = RigidFreedom::Kind::about_line;
    freedom.axis = eigen.eigenvectors().col(2);
  } else {
    freedom.kind = RigidFreedom::Kind::none;
  }
  return freedom;
}

RigidMotion fit_rigid_motion(const RigidFreedom& freedom, const Positions& position,
                             const Positions& velocity, const MassView& mass,
                             const MassView& inverse_mass) {
  RigidMotion rigid;
  if (freedom.kind == RigidFreedom::Kind::none) return rigid;
  const int n = static_cast<int>(position.cols());
  double total = 0.0;  // kg
  Vec3 momentum = Vec3::Zero(), centre = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    if (inverse_mass[i] == 0.0) continue;
    total += mass[i];
    centre += mass[i] * position.col(i);
    momentum += mass[i] * velocity.col(i);
  }
  if (total <= 0.0) return rigid;
  // free: about the centre of mass, which moves with the mean velocity; pinned: about the pins
  const bool free = freedom.kind == RigidFreedom::Kind::free;
  rigid.centre = free ? Vec3(centre / total) : freedom.point;
  if (free) rigid.linear = momentum / total;
  Vec3 angular_momentum = Vec3::Zero();  // about the centre
  Mat3 inertia = Mat3::Zero();
  for (int i = 0; i < n; ++i) {
    if (inverse_mass[i] == 0.0) continue;
    const Vec3 r = position.col(i) - rigid.centre;
    angular_momentum += mass[i] * r.cross(Vec3(velocity.col(i) - rigid.linear));
    inertia += mass[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  if (freedom.kind == RigidFreedom::Kind::about_line) {
    // spin about the pin line only
    const Vec3& u = freedom.axis;
    const double moment = u.dot(inertia * u);
    rigid.angular = moment > 0.0 ? Vec3(u * (u.dot(angular_momentum) / moment)) : Vec3::Zero();
  } else {
    rigid.angular = pseudo_solve(inertia, angular_momentum);
  }
  return rigid;
}

void damp_toward_rigid(const RigidFreedom& freedom, const Positions& position, const MassView& mass,
                       const MassView& inverse_mass, double fraction, Positions& velocity,
                       int threads) {
  if (fraction <= 0.0) return;
  const RigidMotion rigid = fit_rigid_motion(freedom, position, velocity, mass, inverse_mass);
  const int n = static_cast<int>(position.cols());
  parallel_for(0, n, loop_threads(threads, n), [&](int i) {
    if (inverse_mass[i] == 0.0) return;
    velocity.col(i) += fraction * (rigid.at(position.col(i)) - velocity.col(i));
  });
}

}  // namespace chainmail
