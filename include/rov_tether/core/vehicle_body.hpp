#pragma once

#include <limits>
// A vehicle's 6-DOF rigid body in the water, in Fossen's form (docs/model.md, "Vehicle body").

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "rov_tether/core/body_lu.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/vehicle_params.hpp"

namespace rov_tether
{

/// Body velocities [u, v, w, p, q, r] [m/s, rad/s].
using Twist = Vector6;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// What one step did with the thrust command: the wrench it applied and the axes held at their limit.
struct ThrustUsed
{
  /// The thrust applied [N, N m]: the command, each axis held within +-thrust_limit, times the share of the
  /// hull under the water surface (thrusters out of the water push nothing; 1 without a surface).
  Wrench applied = Wrench::Zero();
  /// Bit i set: axis i (surge, sway, heave, roll, pitch, yaw) was commanded beyond its limit and held at it.
  std::uint8_t saturated_axes = 0;
  bool saturated() const { return saturated_axes != 0; }
};

/// What every step of dt from one state needs, whatever its thrust and external wrench: the velocity relative to
/// the water and its magnitude's damping, factored (M + dt D(|nu_r|)), and the restoring wrench. Steps from the same
/// state with the same dt share one (VehicleCoupling: two steps and the end's mobility per sub-step).
struct VehicleStepStart
{
  double dt = 0.0;
  Twist relative =
      Twist::Zero();  ///< nu_r at the start (its momentum kept, should the share have risen since it was set)
  Wrench restoring = Wrench::Zero();   ///< restoringWrench() at the start
  double wet = 1.0;                    ///< submergedShare() at the start: the share of the thrust the water gives
  Matrix6 mass = Matrix6::Identity();  ///< M at that share: the rigid body's and `wet` of the added mass
  Eigen::Vector3d inverse_translational_mass = Eigen::Vector3d::Ones();  ///< its diagonal's head, inverted
  BodyLu damped;                                                         ///< M + dt D(|nu_r|), factored
};

/// What stepped() computed that a second step from the same start, with the same thrust and more external
/// wrench, reuses (stepAgain()): the velocity after parts 1 and 2 and after part 3.
struct VehicleStepTrial
{
  Twist damped = Twist::Zero();  ///< nu_r' (parts 1 and 2)
  Twist turned = Twist::Zero();  ///< nu_r'' (part 3)
  ThrustUsed used;               ///< the thrust applied
};

/**
 * A vehicle's rigid body (Fossen 2011: rigid-body kinetics ch. 3, hydrostatics ch. 4, added mass and damping
 * ch. 6-7, an irrotational constant current ch. 8):
 *
 *   M nu_r' + C(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau_thrust + tau_external,
 *
 * nu = [v; omega] the body velocity, nu_r = nu - [R^T V_c; 0] relative to the water (V_c the current, world
 * frame), M = M_RB + s M_A (rigid body about the body origin with centre of gravity r_G, plus diagonal added
 * mass on the share s of the hull in the water, 1 without a surface), C = C_RB + C_A in the skew-symmetric form C(nu) =
 * [0, -S(p1); -S(p1), -S(p2)] with [p1; p2] = M nu (the rigid-body part equals Fossen's velocity-independent
 * parametrisation, which lets the current enter through nu_r alone), D = diag(linear) + diag(quadratic) |nu_r|, and g
 * the weight m g at r_G and the buoyancy rho g V at r_B. Pose: position in the world frame (z up), attitude a unit
 * quaternion body -> world (no Euler angles, no singularity).
 *
 * Step (h = dt), a split of four exact or stable parts:
 *  1. kick: nu_r += h M^-1 (tau + g(eta_n)) with the saturated thrust;
 *  2. damping, implicit with |nu_r| taken at the step's start: (M + h D_n) nu_r' = M nu_r, which never adds
 *     kinetic energy and decays monotonically per axis at any step; a steady state (thrust against drag) is
 *     exact: F = d_l U + d_q U |U|;
 *  3. Coriolis: (M + h/2 C) nu_r'' = (M - h/2 C) nu_r', a Cayley transform, which keeps the kinetic energy
 *     1/2 nu_r^T M nu_r exactly (C is skew-symmetric) at any step; C is taken at the mean of the two ends
 *     after one fixed-point pass (the implicit midpoint rule: second order for a free body);
 *  4. drift with that mean velocity nu_m = (nu_r' + nu_r'') / 2: attitude *= exp(h omega_m / 2), position +=
 *     h (R_half v_m + V_c) with R_half the attitude half-way through the turn.
 * Parts 1 and 2 are one solve, (M + h D_n) nu_r' = M nu_r + h tau; M + h D_n and M + h/2 C are factored without
 * pivoting, the translational block first (BodyLu: their symmetric parts are positive definite, their
 * translational blocks diagonal), and M + h D_n once for every step from the same start (startStep()).
 * First order in h overall (the kick and the damping are). The one conditional part is the restoring wrench
 * taken explicitly (1, then 4 with the kicked velocity: semi-implicit Euler): under water a spring of stiffness at
 * most k = |B r_B - W r_G| on the smallest effective rotational inertia I' (with added inertia, translation
 * free), stable for h < 2 / sqrt(k / I') (stableStepLimit(): about 1 s for the BlueROV2 Heavy); with a water
 * surface also the heave spring of the hull's buoyancy and thrust crossing it (stableStepLimitAt()).
 * No allocation in step().
 */
class VehicleBody
{
 public:
  /// A body at rest at the origin, upright, with the default (BlueROV2 Heavy) parameters.
  VehicleBody();

  /// Validates and takes new parameters (refused whole, with the message, when invalid); keeps the state.
  Status setParams(const VehicleParams& params);
  const VehicleParams& params() const { return params_; }

  /// Sets the pose (world frame; the attitude is normalised) and the body velocity nu [m/s, rad/s].
  /// Refuses non-finite values and a zero quaternion.
  Status setState(const Eigen::Vector3d& position, const Eigen::Quaterniond& attitude, const Twist& velocity);
  /// The uniform current V_c [m/s], world frame; refuses non-finite values.
  Status setCurrent(const Eigen::Vector3d& current);
  /// The water surface's height [m] in the world (NaN: none, the body always under water). Above it the body
  /// loses its buoyancy, its damping, its thrust and its added mass in proportion to the share of its height
  /// (size.z, centred on the centre of buoyancy) out of the water (submergedShare()): M = M_RB + s M_A. Entering
  /// the water its momentum M nu_r is kept (the added mass it gains slows it: von Karman's water entry); leaving,
  /// its velocity (the water keeps the momentum of the added mass it sheds). Either way the kinetic energy does
  /// not grow. The stable step limit becomes stableStepLimitAt(z).
  void setWaterSurface(double z);
  /// The share of the hull's height under the water surface, in [0, 1] (1 without a surface).
  double submergedShare() const;

  /**
   * Advances the body by dt [s] (0 < dt <= stableStepLimit()) under the thrust command `thrust` (held
   * within +-thrust_limit per axis; `used` says what was applied and which axes were held) and an external
   * body-frame wrench `external` about the body origin (a tether's pull F at a point r is [F; r x F]), both
   * held constant over the step. Refuses non-finite input and a step outside the limit, leaving the state.
   */
  Status step(double dt, const Wrench& thrust, const Wrench& external, ThrustUsed* used);
  /// The same step in two parts: startStep() prepares it from the state as it is (refusing dt as step() does),
  /// and step(start, ...) takes it; steps from one start (the state unchanged in between) share its work.
  Status startStep(double dt, VehicleStepStart* start) const;
  Status step(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external, ThrustUsed* used);
  /// Where step(start, ...) would put the body (position, attitude), the body unchanged. With a `trial`, which
  /// keeps what stepAgain() reuses, part 3 takes its first pass only (C at the start: the position differs
  /// from step()'s by O(h^3)); stepAgain() takes the second.
  Status stepped(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external, Eigen::Vector3d* position,
                 Eigen::Quaterniond* attitude, VehicleStepTrial* trial = nullptr) const;
  /**
   * Takes the step stepped(start, thrust, external, ..., trial) tried, with `more` external wrench (body frame,
   * about the origin) besides: parts 1 and 2 are linear in the wrench, so nu_r' gains h (M + h D_n)^-1 `more`
   * (one solve of the shared factor); part 3 is one Cayley pass, C taken at the mean of nu_r' and the trial's
   * nu_r'' moved by as much (the kinetic energy kept exactly as ever, C being skew-symmetric); part 4 drifts
   * as step() does. The same step as step(start, thrust, external + more) but for part 3's second pass
   * starting from the trial's first (which did not see `more`) moved by what `more` adds: the same order, two
   * factorisations of M + h/2 C for the two steps instead of four. A VehicleCoupling
   * sub-step is one stepped() and one stepAgain() (docs/benchmarks.md, "A dynamic vehicle end"). Refuses a
   * non-finite `more`, leaving the state.
   */
  Status stepAgain(const VehicleStepStart& start, const VehicleStepTrial& trial, const Wrench& more);

  /// The largest stable step [s] in the body's water (setWaterSurface): stableStepLimitAt(its surface).
  double stableStepLimit() const { return stable_step_; }
  /**
   * The largest stable step [s] with the water surface at `surface_z` (NaN: none): 2 / sqrt(lambda), lambda a
   * bound on the largest eigenvalue of M^-1 K, K the stiffness of what the step takes explicitly (class
   * comment). Under water K is the restoring moment's spring, lambda = k c_rot (k = |B r_B - W r_G|, c_rot the
   * largest rotational compliance with translation free: 2 / sqrt(k / I')); infinite with no restoring moment.
   * With a surface the hull crossing it is a spring too: the buoyancy s B and the thrust s tau fall with the
   * share s in the water, whose slope is -1 / size.z along g = [up; r_B x up] (a rise of the centre of
   * buoyancy, body frame). Each part's norm in M's metric bounds its share of lambda: (B / size.z) |g|^2 for
   * the buoyancy, |tau_limit| |g| / size.z for the thrust at its limit, with |g| <= sqrt(c_trans) + |r_B|
   * sqrt(c_rot) (c_trans the largest translational compliance), and the restoring spring with the share anywhere
   * in [0, 1], k = max(|B r_B - W r_G|, |W r_G|); the compliances are M_RB's, out of the water, the largest at
   * any share (M = M_RB + s M_A). Whatever the body's depth, so that the limit does not change as it moves.
   */
  double stableStepLimitAt(double surface_z) const;

  const Eigen::Vector3d& position() const { return position_; }
  const Eigen::Quaterniond& attitude() const { return attitude_; }
  /// Body velocity nu over the ground [u, v, w, p, q, r].
  const Twist& velocity() const { return velocity_; }
  /// Body velocity relative to the water, nu_r = nu - [R^T V_c; 0].
  Twist relativeVelocity() const;
  const Eigen::Vector3d& current() const { return current_; }

  /// M = M_RB + M_A about the body origin, under water.
  const Matrix6& massMatrix() const { return mass_matrix_; }
  /// M_RB + s M_A: the mass matrix with the share s in [0, 1] of the hull in the water.
  Matrix6 massMatrixAt(double share) const;
  /// The restoring wrench -g(eta) (weight at r_G, buoyancy at r_B) acting on the body at this attitude.
  Wrench restoringWrench() const;
  /// Kinetic energy of the body and its added mass relative to the water, 1/2 nu_r^T M nu_r [J] (M at the share in the
  /// water).
  double kineticEnergy() const;
  /// Potential energy in the world, W z_G - B z_B (centres in world coordinates, z up) [J].
  double potentialEnergy() const;

 private:
  void prepare();  // the constant matrices and the step limit from params_
  /// The step from `start`: the end's pose and velocity (skipped when `velocity` is null), and the thrust applied
  /// (no state change).
  Status advance(const VehicleStepStart& start, const Wrench& thrust, const Wrench& external, Eigen::Vector3d* position,
                 Eigen::Quaterniond* attitude, Twist* velocity, ThrustUsed* used, VehicleStepTrial* trial) const;
  /// Part 4: the pose after a step of dt from `position`, `attitude` whose Coriolis part turned nu_r from
  /// `before` to `after`; `velocity` (unless null) is `after` over the ground.
  void drift(double dt, const Twist& before, const Twist& after, Eigen::Vector3d* position,
             Eigen::Quaterniond* attitude, Twist* velocity) const;

  /// M v, M the step's (`start`; six products when M is diagonal).
  Vector6 massTimes(const VehicleStepStart& start, const Vector6& v) const
  {
    return diagonal_mass_ ? Vector6(start.mass.diagonal().cwiseProduct(v)) : Vector6(start.mass * v);
  }
  /// The relative velocity `relative`, set with `from` of the hull in the water, with `to` in it: the momentum
  /// M nu_r kept when `to` is deeper (entering), else the velocity (leaving).
  Twist entered(const Twist& relative, double from, double to) const;
  /// After a step from the share `from`: the velocity for the share the body is at now (entered()), which
  /// velocity_share_ then holds.
  void settleVelocity(double from);
  /// Factors M + a C(momentum) (part 3's Cayley transform), M the step's, into `lu`: without building the 6 x 6
  /// matrix when M is diagonal.
  void factorMassPlusCoriolis(const VehicleStepStart& start, const Vector6& momentum, double a, BodyLu* lu) const;

  VehicleParams params_;
  Matrix6 mass_matrix_ = Matrix6::Identity();
  bool diagonal_mass_ = true;                                             ///< M is diagonal (r_G = 0)
  Eigen::Vector3d inverse_translational_mass_ = Eigen::Vector3d::Ones();  ///< M's diagonal's head, inverted
  double stable_step_ = 0.0;
  /// The largest eigenvalues of M^-1's rotational block under water (M) and of M_RB^-1's rotational and
  /// translational blocks (out of the water: the largest at any share) [1/(kg m^2), 1/kg], for stableStepLimitAt.
  double rotational_compliance_ = 0.0;
  double dry_rotational_compliance_ = 0.0;
  double dry_translational_compliance_ = 0.0;

  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond attitude_ = Eigen::Quaterniond::Identity();
  Twist velocity_ = Twist::Zero();
  Eigen::Vector3d current_ = Eigen::Vector3d::Zero();
  double water_surface_z_ = std::numeric_limits<double>::quiet_NaN();
  /// The share in the water for which velocity_ holds (a step's end, setState): a step that starts deeper in (the
  /// surface moved, a state set) keeps the momentum.
  double velocity_share_ = 1.0;
  /// The centre of buoyancy's height [m] in the world.
  double buoyancyHeight() const;
};

}  // namespace rov_tether
