#include "rov_tether/core/vehicle_coupling.hpp"

#include <Eigen/Eigenvalues>
#include <limits>

namespace rov_tether
{

VehicleCoupling::VehicleCoupling(const VehicleBody& body, const Eigen::Vector3d& offset) : body_(body), offset_(offset)
{
}

Status VehicleCoupling::setThrust(const Wrench& thrust)
{
  if (!thrust.allFinite())
  {
    return Status::error("vehicle thrust rejected: every component must be finite");
  }
  thrust_ = thrust;
  return Status::success();
}

Status VehicleCoupling::setLoad(const Force& force, const Eigen::Vector3d& moment)
{
  if (!force.allFinite() || !moment.allFinite())
  {
    return Status::error("vehicle load rejected: every component must be finite");
  }
  load_force_ = force;
  load_moment_ = moment;
  loaded_ = !force.isZero(0.0) || !moment.isZero(0.0);
  started_ = false;
  return Status::success();
}

Wrench VehicleCoupling::load() const
{
  Wrench wrench = Wrench::Zero();
  if (loaded_)
  {
    const Eigen::Quaterniond to_body = body_.attitude().conjugate();
    wrench << to_body * load_force_, to_body * load_moment_;
  }
  return wrench;
}

Status VehicleCoupling::predict(double h, Position* predicted)
{
  started_ = false;
  const Status started = body_.startStep(h, &start_);
  if (!started)
  {
    return started;
  }
  started_ = true;
  Eigen::Vector3d position;
  Eigen::Quaterniond attitude;
  const Status stepped = body_.stepped(start_, thrust_, load(), &position, &attitude, &trial_);
  if (stepped)
  {
    *predicted = position + attitude * offset_;
  }
  return stepped;
}

Eigen::Matrix3d VehicleCoupling::pointMobility(const VehicleStepStart& start) const
{
  // The body's step answers a wrench tau held over it by h (M + h D)^-1 tau in velocity (the kick, then the
  // implicit damping at the step's start speed: start.damped), and by h^2 times that in pose. A force F at the
  // offset r is the wrench G^T F = [F; r x F], and the point moves by G = [I, -S(r)] of the pose change.
  Eigen::Matrix<double, 6, 3> wrench_of_force;
  wrench_of_force.topRows<3>().setIdentity();
  wrench_of_force.bottomRows<3>() << 0.0, -offset_.z(), offset_.y(), offset_.z(), 0.0, -offset_.x(), -offset_.y(),
      offset_.x(), 0.0;  // S(r): r x F
  const Eigen::Matrix<double, 6, 3> motion = start.damped.solve(wrench_of_force);
  return wrench_of_force.transpose() * motion;  // G^T = [I; S(r)], so G = [I, S(r)^T] = [I, -S(r)]
}

double VehicleCoupling::inverseMass(const Position& neighbour, const Position& predicted, double h) const
{
  VehicleStepStart fallback;
  if (!(started_ && start_.dt == h) && !body_.startStep(h, &fallback))
  {
    return 0.0;  // a step the body refuses (predict() says why): held as the kinematic end is
  }
  const VehicleStepStart& start = started_ && start_.dt == h ? start_ : fallback;  // predict()'s factorisation
  const Position along = predicted - neighbour;
  const double length_squared = along.squaredNorm();
  if (!(length_squared >= std::numeric_limits<double>::min()))  // (not subnormal: 1 / |a|^2 stays finite)
  {
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(pointMobility(start), Eigen::EigenvaluesOnly)
        .eigenvalues()
        .maxCoeff();
  }
  // n^T W_p n = (G^T n)^T (M + h D)^-1 (G^T n), G^T n = [n; r x n]: one solve along n, not W_p's three; taken
  // along the unnormalised a = |a| n and divided by |a|^2 (one division, no square root).
  const Eigen::Vector3d a = body_.attitude().conjugate() * along;
  Vector6 wrench;
  wrench << a, offset_.cross(a);
  return wrench.dot(start.damped.solve(wrench)) / length_squared;
}

Status VehicleCoupling::finish(double h, const Force& pull, Position* attachment_point)
{
  if (!pull.allFinite())
  {
    return Status::error("vehicle coupling: the tether's pull is not finite");
  }
  const Eigen::Vector3d force = body_.attitude().conjugate() * pull;
  Wrench external;
  external << force, offset_.cross(force);
  Status stepped = Status::success();
  if (started_ && start_.dt == h)
  {
    // predict()'s step with the pull besides (VehicleBody::stepAgain: the pull's kick and one Coriolis pass).
    stepped = body_.stepAgain(start_, trial_, external);
    used_ = trial_.used;
  }
  else
  {
    const Status started = body_.startStep(h, &start_);
    if (!started)
    {
      *attachment_point = attachment();
      return started;
    }
    stepped = body_.step(start_, thrust_, load() + external, &used_);
  }
  started_ = false;  // the body moves on
  if (stepped)
  {
    pull_ = pull;
  }
  *attachment_point = attachment();
  return stepped;
}

}  // namespace rov_tether
