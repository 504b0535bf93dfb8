#include "rov_tether/core/vehicle_body.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rov_tether
{
namespace
{

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;

// S(a) b = a x b.
Matrix3 skew(const Vector3& a)
{
  Matrix3 s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

// Fossen's skew-symmetric Coriolis-centripetal matrix of a symmetric mass matrix M at nu (Fossen 2011,
// ch. 3 and 6): C(nu) = [0, -S(p1); -S(p1), -S(p2)], [p1; p2] = M nu = `momentum`. The Cayley transform needs
// only M + a C (three skew blocks added to M) and C b, which is [b_w x p1; b_v x p1 + b_w x p2] for b = [b_v; b_w].
// Adds -S(q) = [0, q_z, -q_y; -q_z, 0, q_x; q_y, -q_x, 0] to the 3x3 block of `sum` at (row, col).
void addMinusSkew(Matrix6& sum, int row, int col, const Vector3& q)
{
  sum(row, col + 1) += q.z();
  sum(row, col + 2) -= q.y();
  sum(row + 1, col) -= q.z();
  sum(row + 1, col + 2) += q.x();
  sum(row + 2, col) += q.y();
  sum(row + 2, col + 1) -= q.x();
}

Matrix6 massPlusCoriolis(const Matrix6& mass, const Vector6& momentum, double a)
{
  const Vector3 q1 = a * momentum.head<3>();
  Matrix6 sum = mass;
  addMinusSkew(sum, 0, 3, q1);
  addMinusSkew(sum, 3, 0, q1);
  addMinusSkew(sum, 3, 3, a * momentum.tail<3>());
  return sum;
}

Vector6 coriolisTimes(const Vector6& momentum, const Vector6& b)
{
  Vector6 product;
  product.head<3>() = b.tail<3>().cross(momentum.head<3>());
  product.tail<3>() = b.head<3>().cross(momentum.head<3>()) + b.tail<3>().cross(momentum.tail<3>());
  return product;
}

bool finite(const Vector6& values) { return values.allFinite(); }

// exp(turn / 4) as a unit quaternion, the rotation by half of the angle |turn| about turn's axis: [cos(a / 4),
// sin(a / 4) turn / a]. A sub-step turns a body by hundredths of a radian, where the Taylor series to x^7 is
// exact in double precision (the first term left out, x^9 / 9!, is below 3e-18 of sin x for x = a / 4 <= 1/32)
// and costs a tenth of a call to sincos; larger turns call it.
Eigen::Quaterniond halfTurn(const Vector3& turn)
{
  const double angle_squared = turn.squaredNorm();
  const double x2 = angle_squared / 16.0;  // (a / 4)^2
  if (x2 <= 1.0 / 1024.0)
  {
    // Multiplications by the coefficients, not divisions by their inverses: seven divisions in series would
    // be the body step's longest chain.
    constexpr double k6 = 1.0 / 6.0, k12 = 1.0 / 12.0, k20 = 1.0 / 20.0, k30 = 1.0 / 30.0, k42 = 1.0 / 42.0,
                     k56 = 1.0 / 56.0;
    const double sine_over_angle = 0.25 * (1.0 - x2 * k6 * (1.0 - x2 * k20 * (1.0 - x2 * k42)));  // sin(a/4) / a
    const double cosine = 1.0 - 0.5 * x2 * (1.0 - x2 * k12 * (1.0 - x2 * k30 * (1.0 - x2 * k56)));
    return Eigen::Quaterniond(cosine, sine_over_angle * turn.x(), sine_over_angle * turn.y(),
                              sine_over_angle * turn.z());
  }
  const double angle = std::sqrt(angle_squared);
  return Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * angle, turn / angle));
}

std::string number(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

}  // namespace

VehicleBody::VehicleBody() { prepare(); }

Status VehicleBody::setParams(const VehicleParams& params)
{
  const Status valid = params.validate();
  if (!valid)
  {
    return valid;
  }
  params_ = params;
  prepare();
  return Status::success();
}

void VehicleBody::prepare()
{
  const double m = params_.mass;
  const Vector3& r_g = params_.center_of_gravity;
  const Matrix3 s_g = skew(r_g);
  // Rigid body about the origin (Fossen 2011, ch. 3): [m I, -m S(r_G); m S(r_G), I_G - m S(r_G)^2].
  Matrix6 rigid;
  rigid.topLeftCorner<3, 3>() = m * Matrix3::Identity();
  rigid.topRightCorner<3, 3>() = -m * s_g;
  rigid.bottomLeftCorner<3, 3>() = m * s_g;
  rigid.bottomRightCorner<3, 3>() = Matrix3(params_.inertia.asDiagonal()) - m * s_g * s_g;
  mass_matrix_ = rigid;
  mass_matrix_.diagonal() += params_.added_mass;
  const Eigen::LDLT<Matrix6> mass_factor(mass_matrix_);
  // A body whose origin is its centre of gravity (most published models, the BlueROV2 Heavy's) has a diagonal
  // M: its products are six multiplications.
  diagonal_mass_ = mass_matrix_.isDiagonal(0.0);
  inverse_translational_mass_ = mass_matrix_.diagonal().head<3>().cwiseInverse();

  // The restoring moment is a spring on the attitude of stiffness at most k = |B r_B - W r_G| (the norm of
  // the Hessian of the potential -e_z^T R (B r_B - W r_G) in a small rotation). It turns the smallest
  // effective rotational inertia I' (translation free: the inverse of M^-1's rotational block) at
  // omega_n = sqrt(k / I'); semi-implicit Euler on a spring is stable for h omega_n < 2.
  // (stableStepLimitAt: with a water surface, the hull crossing it adds the springs of its buoyancy and thrust.)
  const Matrix6 inverse = mass_factor.solve(Matrix6::Identity());
  const auto largest = [](const Matrix3& block)
  { return Eigen::SelfAdjointEigenSolver<Matrix3>(0.5 * (block + block.transpose())).eigenvalues().maxCoeff(); };
  rotational_compliance_ = largest(inverse.bottomRightCorner<3, 3>());
  const Matrix6 dry = Eigen::LDLT<Matrix6>(rigid).solve(Matrix6::Identity());  // out of the water: no added mass
  dry_rotational_compliance_ = largest(dry.bottomRightCorner<3, 3>());
  dry_translational_compliance_ = largest(dry.topLeftCorner<3, 3>());
  stable_step_ = stableStepLimitAt(water_surface_z_);
}

double VehicleBody::stableStepLimitAt(double surface_z) const
{
  const Vector3& r_g = params_.center_of_gravity;
  const Vector3& r_b = params_.center_of_buoyancy;
  const double submerged_spring = (params_.buoyancy() * r_b - params_.weight() * r_g).norm();
  double lambda = submerged_spring * rotational_compliance_;
  if (!std::isnan(surface_z))
  {
    // The share s in [0, 1] scales the buoyancy: its spring on the attitude is largest at one end or the other. It
    // scales the added mass too: the compliances are largest out of the water (M_RB <= M_RB + s M_A).
    const double rotational = dry_rotational_compliance_, translational = dry_translational_compliance_;
    lambda = std::max(submerged_spring, params_.weight() * r_g.norm()) * rotational;
    const double height = params_.size.z();
    const double along = std::sqrt(translational) + r_b.norm() * std::sqrt(rotational);
    const double thrust = std::sqrt(translational) * params_.thrust_limit.head<3>().norm() +
                          std::sqrt(rotational) * params_.thrust_limit.tail<3>().norm();
    lambda += params_.buoyancy() / height * along * along + thrust * along / height;
  }
  return lambda > 0.0 ? 2.0 / std::sqrt(lambda) : std::numeric_limits<double>::infinity();
}

void VehicleBody::setWaterSurface(double z)
{
  if (std::isnan(z) != std::isnan(water_surface_z_))
  {
    stable_step_ = stableStepLimitAt(z);  // the limit depends on there being a surface, not on its height
  }
  // velocity_share_ stays: a surface moved past the body is met as the body meeting it (the next step keeps the
  // momentum where the share rose, the velocity where it fell), so the kinetic energy does not grow either way.
  water_surface_z_ = z;
}

Twist VehicleBody::entered(const Twist& relative, double from, double to) const
{
  if (!(to > from) || !params_.added_mass.any())
  {
    return relative;  // out of the water, or no deeper: the velocity stays (the water keeps the shed momentum)
  }
  // Deeper in: the added mass it gains keeps the momentum M nu_r (von Karman's water entry), which slows it; the
  // kinetic energy 1/2 p^T M^-1 p falls as M grows.
  const Vector6 momentum = massMatrixAt(from) * relative;
  const Matrix6 mass = massMatrixAt(to);
  return diagonal_mass_ ? Twist(momentum.cwiseQuotient(mass.diagonal()))
                        : Twist(Eigen::LDLT<Matrix6>(mass).solve(momentum));
}

void VehicleBody::settleVelocity(double from)
{
  const double now = submergedShare();
  if (now > from && params_.added_mass.any())  // deeper in: the momentum kept (otherwise the velocity, untouched)
  {
    velocity_ = entered(relativeVelocity(), from, now);
    velocity_.head<3>() += attitude_.conjugate() * current_;
  }
  velocity_share_ = now;
}

Matrix6 VehicleBody::massMatrixAt(double share) const
{
  Matrix6 mass = mass_matrix_;
  mass.diagonal() -= (1.0 - share) * params_.added_mass;
  return mass;
}

void VehicleBody::factorMassPlusCoriolis(const VehicleStepStart& start, const Vector6& momentum, double a,
                                         BodyLu* lu) const
{
  if (diagonal_mass_)
  {
    lu->computeGyroscopic(start.inverse_translational_mass, start.mass.diagonal().tail<3>(), a * momentum.head<3>(),
                          a * momentum.tail<3>());
    return;
  }
  lu->compute(massPlusCoriolis(start.mass, momentum, a));
}

Status VehicleBody::setState(const Eigen::Vector3d& position, const Eigen::Quaterniond& attitude, const Twist& velocity)
{
  if (!position.allFinite() || !attitude.coeffs().allFinite() || !finite(velocity))
  {
    return Status::error("vehicle state: position, attitude and velocity must be finite");
  }
  if (attitude.norm() < 1e-9)
  {
    return Status::error("vehicle state: the attitude quaternion must not be zero");
  }
  position_ = position;
  attitude_ = attitude.normalized();
  velocity_ = velocity;
  velocity_share_ = submergedShare();
  return Status::success();
}

Status VehicleBody::setCurrent(const Eigen::Vector3d& current)
{
  if (!current.allFinite())
  {
    return Status::error("vehicle current: must be finite");
  }
  current_ = current;
  return Status::success();
}

Twist VehicleBody::relativeVelocity() const
{
  Twist relative = velocity_;
  relative.head<3>() -= attitude_.conjugate() * current_;
  return relative;
}

double VehicleBody::buoyancyHeight() const { return position_.z() + (attitude_ * params_.center_of_buoyancy).z(); }

double VehicleBody::submergedShare() const
{
  if (std::isnan(water_surface_z_))
  {
    return 1.0;
  }
  const double height = params_.size.z();
  return std::clamp((water_surface_z_ - (buoyancyHeight() - 0.5 * height)) / height, 0.0, 1.0);
}

Wrench VehicleBody::restoringWrench() const
{
  const Vector3 up = attitude_.conjugate() * Vector3::UnitZ();  // world z in the body frame
  const Vector3 weight = -params_.weight() * up;
  const Vector3 buoyancy = submergedShare() * params_.buoyancy() * up;  // what is out of the water displaces none
  Wrench wrench;
  wrench.head<3>() = weight + buoyancy;
  wrench.tail<3>() = params_.center_of_gravity.cross(weight) + params_.center_of_buoyancy.cross(buoyancy);
  return wrench;
}

double VehicleBody::kineticEnergy() const
{
  const Twist relative = relativeVelocity();
  return 0.5 * relative.dot(massMatrixAt(submergedShare()) * relative);
}

double VehicleBody::potentialEnergy() const
{
  const double z_g = position_.z() + (attitude_ * params_.center_of_gravity).z();
  double z_b = buoyancyHeight();
  if (!std::isnan(water_surface_z_))
  {
    // The buoyancy's potential is -B times the integral of the submerged share s over the height: z_b while all
    // of the hull is under water, then the ramp's integral across the surface, then constant (out of the water).
    const double height = params_.size.z();
    const double wet_top = water_surface_z_ - 0.5 * height;  // z_b at which the hull's top reaches the surface
    const double across = std::clamp(z_b - wet_top, 0.0, height);
    z_b = std::min(z_b, wet_top) + across - 0.5 * across * across / height;
  }
  return params_.weight() * z_g - params_.buoyancy() * z_b;
}

Status VehicleBody::startStep(double dt, VehicleStepStart* start) const
{
  if (!(dt > 0.0) || !(dt <= stable_step_))
  {
    return Status::error("vehicle step: dt must be in (0, " + number(stable_step_) + "] s, the stability limit of " +
                         (std::isnan(water_surface_z_) ? "the restoring moment"
                                                       : "the restoring moment and the surface's buoyancy and thrust") +
                         " (got " + number(dt) + ")");
  }
  start->dt = dt;
  start->relative = velocity_;
  start->relative.head<3>() -= attitude_.conjugate() * current_;
  start->restoring = restoringWrench();
  start->wet = submergedShare();
  if (start->wet == 1.0)
  {
    start->mass = mass_matrix_;  // under water (and always without a surface): as prepared
    start->inverse_translational_mass = inverse_translational_mass_;
  }
  else
  {
    start->mass = massMatrixAt(start->wet);
    start->inverse_translational_mass = start->mass.diagonal().head<3>().cwiseInverse();
  }
  // Deeper in the water than where its velocity was set (a state or a surface set since): the momentum is kept.
  start->relative = entered(start->relative, velocity_share_, start->wet);
  // The damping of step 2, implicit per axis with |nu_r| from the step's start (exact at a steady state).
  // The water's damping acts on the share of the hull in it.
  const Vector6 damping =
      dt * start->wet * (params_.linear_damping + params_.quadratic_damping.cwiseProduct(start->relative.cwiseAbs()));
  if (diagonal_mass_)
  {
    start->damped.computeDiagonal(start->mass.diagonal() + damping);  // six divisions
  }
  else
  {
    Matrix6 damped = start->mass;
    damped.diagonal() += damping;
    start->damped.compute(damped);
  }
  return Status::success();
}

Status VehicleBody::step(double dt, const Wrench& thrust, const Wrench& external, ThrustUsed* used)
{
  VehicleStepStart start;
  const Status started = startStep(dt, &start);
  return started ? step(start, thrust, external, used) : started;
}

Status VehicleBody::step(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external, ThrustUsed* used)
{
  const Status stepped = advance(start, thrust, external, &position_, &attitude_, &velocity_, used, nullptr);
  if (stepped)
  {
    settleVelocity(start.wet);  // the step's velocity is for M at its start's share: now at the share it ends at
  }
  return stepped;
}

Status VehicleBody::stepped(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external,
                            Eigen::Vector3d* position, Eigen::Quaterniond* attitude, VehicleStepTrial* trial) const
{
  *position = position_;
  *attitude = attitude_;
  return advance(start, thrust, external, position, attitude, nullptr, nullptr, trial);
}

Status VehicleBody::stepAgain(const VehicleStepStart& start, const VehicleStepTrial& trial, const Wrench& more)
{
  if (!finite(more))
  {
    return Status::error("vehicle step: the external wrench must be finite");
  }
  const double dt = start.dt;
  const Twist before = trial.damped + dt * start.damped.solve(more);
  // C at the mean of the ends, the far end guessed as the trial's moved by what `more` added (the implicit
  // midpoint rule's one pass, as step()'s second).
  const Vector6 momentum = massTimes(start, before + 0.5 * (trial.turned - trial.damped));
  BodyLu cayley;
  factorMassPlusCoriolis(start, momentum, 0.5 * dt, &cayley);
  const Twist after = cayley.solve(Twist(massTimes(start, before) - 0.5 * dt * coriolisTimes(momentum, before)));
  drift(dt, before, after, &position_, &attitude_, &velocity_);
  settleVelocity(start.wet);
  return Status::success();
}

Status VehicleBody::advance(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external,
                            Eigen::Vector3d* position, Eigen::Quaterniond* attitude, Twist* velocity, ThrustUsed* used,
                            VehicleStepTrial* trial) const
{
  if (!finite(thrust) || !finite(external))
  {
    return Status::error("vehicle step: thrust and external wrench must be finite");
  }
  const double dt = start.dt;
  // Thrust held within its limit per axis, and reported.
  ThrustUsed applied;
  for (int i = 0; i < 6; ++i)
  {
    const double limit = params_.thrust_limit[i];
    applied.applied[i] = thrust[i] > limit ? limit : (thrust[i] < -limit ? -limit : thrust[i]);
    if (applied.applied[i] != thrust[i])
    {
      applied.saturated_axes |= static_cast<std::uint8_t>(1u << i);
    }
  }
  applied.applied *= start.wet;  // the thrusters' share in the water

  // 1. Kick: thrust, external wrench and the restoring wrench at this attitude, nu_k = nu_r + h M^-1 tau; and
  // 2. damping, implicit per axis with |nu_r| from the step's start: (M + h D) nu' = M nu_k = M nu_r + h tau
  // (start.damped), one solve for both.
  Twist relative =
      start.damped.solve(Twist(massTimes(start, start.relative) + dt * (applied.applied + external + start.restoring)));

  // 3. Coriolis and centripetal terms: a Cayley transform (M + h/2 C) nu' = (M - h/2 C) nu with C frozen keeps
  // nu^T M nu exactly, C being skew-symmetric. C is taken at the step's start, then once more at the mean of
  // the two ends (one pass of the implicit midpoint rule): frozen at the start alone, the body's momentum
  // would turn with a first-order error in its length.
  const Twist before = relative;
  const Vector6 momentum_before = massTimes(start, before);
  Twist turned = before;
  // A trial (stepped() for stepAgain()) takes the first pass only: C at the start, where the body goes to
  // O(h^3) in position; stepAgain() takes the second from it. (An explicit midpoint step in its place, which
  // needs no factorisation, fails VehicleBody.StepAgainIsTheWholeStepWithTheAddedWrench: the coupled step
  // strays from step() by more than step()'s own error.)
  const int passes = trial != nullptr ? 1 : 2;
  for (int pass = 0; pass < passes; ++pass)
  {
    // C's argument M nu, at the mean of the two ends: on the first pass both are `before`.
    const Vector6 momentum = pass == 0 ? momentum_before : massTimes(start, 0.5 * (before + turned));
    BodyLu cayley;  // M + h/2 C: its symmetric part is M, its translational block diagonal
    factorMassPlusCoriolis(start, momentum, 0.5 * dt, &cayley);
    turned = cayley.solve(Twist(momentum_before - 0.5 * dt * coriolisTimes(momentum, before)));
  }
  if (trial != nullptr)
  {
    trial->damped = before;
    trial->turned = turned;
    trial->used = applied;
  }
  drift(dt, before, turned, position, attitude, velocity);
  if (used != nullptr)
  {
    *used = applied;
  }
  return Status::success();
}

void VehicleBody::drift(double dt, const Twist& before, const Twist& after, Eigen::Vector3d* position,
                        Eigen::Quaterniond* attitude, Twist* velocity) const
{
  // 4. Drift with the velocity the Coriolis step turned (the mean of its two ends, the rate at which it
  // turned the momentum): position by R v_r + V_c, attitude by the body rate's exponential.
  const Twist mean = 0.5 * (before + after);
  const Vector3 turn = dt * mean.tail<3>();
  const Eigen::Quaterniond half_turn = halfTurn(turn);  // exp(h omega / 2): the attitude halfway
  const Eigen::Quaterniond half_way = *attitude * half_turn;
  *position += dt * (half_way * mean.head<3>() + current_);
  // The whole turn: exp(h omega / 2) twice. The product of unit quaternions is unit to rounding, |q|^2 = 1 + e with
  // |e| of a few 1e-16: one Newton step for 1 / sqrt(|q|^2), (3 - |q|^2) / 2 = 1 - e / 2 + O(e^2), renormalises it
  // as q / |q| would to within e^2, without a square root or a division.
  const Eigen::Quaterniond whole = half_way * half_turn;
  attitude->coeffs() = (0.5 * (3.0 - whole.squaredNorm())) * whole.coeffs();
  if (velocity != nullptr)
  {
    *velocity = after;
    velocity->head<3>() += attitude->conjugate() * current_;
  }
}

}  // namespace rov_tether
