#pragma once
// The built-in controller of a dynamic vehicle: a setpoint (a world position and a yaw) and the body's state
// in, a body-frame thrust wrench out (docs/model.md, "Vehicle controller"). ROS-free.

#include <Eigen/Core>
#include <cstdint>

#include "rov_tether/core/status.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/core/vehicle_params.hpp"

namespace rov_tether
{

/// The controlled axes, in this order: surge, sway, heave (body frame) and yaw.
using Vector4 = Eigen::Vector4d;

/// How the default gains are designed from a vehicle (ControllerGains::design).
struct ControllerDesign
{
  /// Natural frequency omega of the loop's oscillatory pole pair per axis (surge, sway, heave, yaw) [rad/s].
  /// 1 rad/s in translation keeps a 4 m step of the BlueROV2 Heavy within its surge thrust (kp 27.8 N/m);
  /// 2 rad/s in yaw, where its inertia is small against its yaw thrust: the yaw loop stays unsaturated for
  /// any wrapped error (kp 3.3 N m/rad, pi rad: 10.4 of 30.4 N m).
  Vector4 bandwidth{1.0, 1.0, 1.0, 2.0};
  /// Damping ratio zeta of that pair: 1, critically damped.
  double damping_ratio = 1.0;
  /// The integral's pole at -integral_ratio * omega: slow against the pair, so it removes a steady offset
  /// (a current, a tether's pull) in about 1 / (integral_ratio omega) = 5 s without changing the pair.
  double integral_ratio = 0.2;
  /// Natural frequency of the level hold on roll and pitch [rad/s]: a critically damped PD per axis with
  /// kp = I' omega^2, kd = 2 omega I' - d (I' inertia with added inertia, d linear damping; kd held at 0 when
  /// negative: the vehicle damps more; damping_ratio is the translation's and yaw's only); 0, none (roll and pitch left
  /// to the restoring moment). Default 8 rad/s: left to its restoring moment (W BG = 1.3 N m/rad), the BlueROV2 Heavy
  /// turns broadside under the added-mass (Munk) moment, stiffness (m33' - m11') U^2 = 12.3 U^2 N m/rad, above U = 0.33
  /// m/s (a 0.5 m/s path pitched it past 30 degrees); at 8 rad/s kp = 23.4 N m/rad in pitch, 2.6 times the Munk
  /// stiffness at its full-thrust surge speed (0.85 m/s), and the hold still settles at the largest time_step, 0.1 s
  /// (10 rad/s does not). Both are tested (test_vehicle_controller.cpp).
  double level_bandwidth = 8.0;

  /// Finite; bandwidth > 0; damping_ratio > 0; integral_ratio, level_bandwidth >= 0. Names the field and value.
  Status validate() const;
};

/**
 * Gains of the four PID loops, per axis in Vector4's order (surge, sway, heave [N, m, s]; yaw [N m, rad, s]).
 *
 * Defaults: ControllerGains::design(VehicleParams{}, ControllerDesign{}), the BlueROV2 Heavy with omega 1 rad/s
 * in translation and 2 rad/s in yaw, zeta 1, integral pole at 0.2 omega (a test checks that the numbers below
 * are that design's). The design places the poles of each axis's loop linearised at rest,
 *   m' x'' + d x' = u,   u = kp e + ki int(e) - kd x'     (m' = mass + added mass, d = linear damping),
 * whose characteristic polynomial m' s^3 + (d + kd) s^2 + kp s + ki is made m' (s^2 + 2 zeta omega s +
 * omega^2)(s + omega_i), omega_i = integral_ratio omega:
 *   kp = m' (omega^2 + 2 zeta omega omega_i),  ki = m' omega^2 omega_i,  kd = m' (2 zeta omega + omega_i) - d.
 * with m' = mass + added_mass[i] (yaw: inertia z + added_mass[5]; the centre of gravity's cross terms left
 * out) and d = linear_damping[i]. Quadratic damping is zero at rest; moving, it only damps the loop more.
 * BlueROV2 Heavy: m' 19.86, 20.62, 32.18 kg and 0.592 kg m^2, d 13.7, 0, 33.0 N s/m and 0 N m s.
 * The closed loop's step response (setpoint to position, linearised) is that third-order system's, with the
 * integral's zero at -ki / kp: it overshoots by 16.9% with these ratios (within the thrust limits;
 * test VehicleController.SurgeStepFollowsTheLinearisedLoop), the price of integral action on the error.
 */
struct ControllerGains
{
  /// kp [N/m; N m/rad]: on the error e (setpoint - position, in the body frame; wrapped yaw error).
  Vector4 proportional{27.804, 28.868, 45.052, 3.3152};
  /// ki [N/(m s); N m/(rad s)]: on the error's integral.
  Vector4 integral{3.972, 4.124, 6.436, 0.9472};
  /// kd [N s/m; N m s/rad]: on the measured velocity (minus the feed-forward velocity), never on the
  /// error's rate, so a setpoint step gives no kick.
  Vector4 derivative{29.992, 45.364, 37.796, 2.6048};
  /// Largest |integral term| [N; N m]: the BlueROV2 Heavy's thrust limits, so the integral alone never asks
  /// for more than the thrusters give. Reaching it is reported (ControllerOutput::integral_held_axes).
  Vector4 integral_limit{113.7, 113.7, 160.8, 30.4};
  /// Anti-windup by conditional integration (VehicleController). Off only to show what it prevents (tests).
  bool anti_windup = true;
  /// Level hold, a PD on roll and pitch [N m/rad; N m s/rad] (roll, pitch) towards level, placed by
  /// ControllerDesign::level_bandwidth (8 rad/s: I' 64 and 16 I' - d); 0 leaves the two axes to the restoring
  /// moment.
  Eigen::Vector2d level_proportional{28.736, 23.36};
  Eigen::Vector2d level_derivative{7.184, 5.04};

  /// Finite; proportional > 0; integral, derivative, integral_limit, level gains >= 0. Names the field, axis
  /// and value.
  Status validate() const;

  /// The pole-placement design above for `vehicle`, the integral limited at its thrust limits. kd is
  /// m' (2 zeta omega + omega_i) - d; a vehicle damped more than that (kd < 0) is refused, naming the axis:
  /// ask for a higher bandwidth.
  static Status design(const VehicleParams& vehicle, const ControllerDesign& design, ControllerGains* gains);
};

/// What one update commanded.
struct ControllerOutput
{
  /// Body-frame thrust [Fx, Fy, Fz, Mx, My, Mz] [N, N m], each axis within the vehicle's thrust_limit; roll
  /// and pitch 0 with the level hold's gains 0.
  Wrench thrust = Wrench::Zero();
  /// Bit i set (ThrustUsed's numbering: 0 surge, 1 sway, 2 heave, 3 roll, 4 pitch, 5 yaw): the controller
  /// asked for more than the limit on that axis and was held at it.
  std::uint8_t saturated_axes = 0;
  /// Bit i set (same numbering): the integral term acting on that axis was held at its integral_limit in this
  /// update (integrating would have taken it beyond, or a turn put more on the axis than its limit).
  std::uint8_t integral_held_axes = 0;
  /// The update's dt exceeds VehicleController::levelStepLimit(): the level hold swings up instead of settling
  /// (the node warns: raise physics_rate or lower level_bandwidth).
  bool level_step_too_long = false;
};

/// A setpoint: where the vehicle should be, and optionally how fast the setpoint moves.
struct VehicleSetpoint
{
  /// Position of the body origin, world frame [m].
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  /// Heading [rad]: the angle of the body's x axis in the world's x-y plane from world x, counter-clockwise.
  double yaw = 0.0;
  /// Feed-forward velocity of the setpoint, world frame [m/s] (0: hold a point).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Feed-forward yaw rate [rad/s].
  double yaw_rate = 0.0;
};

/**
 * Per-axis PID from a setpoint to a body-frame thrust, as ROV position controllers are built (Fossen 2011,
 * ch. 12, "PID control"; Astrom and Hagglund, "Advanced PID Control", 2006, ch. 3, for the windup):
 *  - surge, sway, heave: the world error setpoint - position rotated into the body frame by the attitude,
 *    e = R^T (p_ref - p); the derivative term acts on the measured body velocity, kd (R^T v_ff - v). The
 *    world error is first bounded, its horizontal part's length and its vertical part each to twice the
 *    error at which the P term alone meets the thrust limit (the larger of surge's and sway's horizontally),
 *    keeping its direction: a far setpoint then asks what one at that reach asks, and a small tilt cannot
 *    turn a long horizontal error into a saturated heave;
 *  - yaw: the heading error wrapped to [-pi, pi] (the short way round), the derivative on the body yaw rate r
 *    (the heading's rate while the vehicle is level);
 *  - roll and pitch: the level hold (level_proportional, level_derivative: a PD on the tilt, as an
 *    autopilot's stabilised mode) keeps the vehicle level: torque kp (z_b x up) - kd [p, q] on roll and pitch,
 *    `up` the world's z in the body frame, held at the roll and pitch thrust limits (reported in bits 3 and
 *    4). With its gains 0 the restoring moment alone rights the vehicle (the centre of buoyancy above the
 *    centre of gravity: 0.01 m on the BlueROV2 Heavy, 1.3 N m/rad). That is weak against the added-mass
 *    (Munk) moment (Z_wdot - X_udot) u w = 12.3 u w N m of a vehicle moving forward and tilted or sinking:
 *    above 0.33 m/s it turns the BlueROV2 Heavy broadside.
 * Each axis's output kp e + I + D is held within +-thrust_limit (reported, ControllerOutput).
 *
 * Anti-windup: conditional integration (clamping). The integral is advanced, I += ki e dt, only when the
 * output is within its limit or the error would pull it back inside; while the output is held at its limit
 * and the error pushes further out, I stays as it is. A hull wholly above the water surface gets none of its
 * thrust (VehicleBody::submergedShare), so there I stays as it is whatever the output; partly above, it gets its
 * wet share of the output held within the limit, so asking more still pushes harder and I goes on. Chosen over
 * back-calculation because it needs no tracking time constant per vehicle and leaves I unchanged during a long
 * saturation (a far setpoint, a vehicle held by its tether), where back-calculation drives I to whatever keeps the
 * unsaturated output at the limit: a large opposite value when the proportional term alone exceeds it, which then has
 * to unwind. The integral term is also held within +-integral_limit. The integrator is forward Euler: the output uses I
 * from before this update.
 * No allocation in update() (fixed-size Eigen only).
 */
class VehicleController
{
 public:
  /// The default gains (the BlueROV2 Heavy's) for the default vehicle.
  VehicleController() = default;

  /// Validates `gains` and checks each axis's loop linearised at rest against `vehicle`: it is stable when
  /// (d + kd) kp > m' ki (Routh-Hurwitz for m' s^3 + (d + kd) s^2 + kp s + ki). Refused whole, with the
  /// axis, the values and the rule, and nothing changes; on success the integrals restart at 0.
  Status configure(const VehicleParams& vehicle, const ControllerGains& gains);
  const ControllerGains& gains() const { return gains_; }

  /// One update of dt [s] > 0: the thrust for `body` to reach `setpoint`. Refuses a non-finite setpoint or
  /// dt <= 0 (nothing changes). The thrust limits are those configure() was given.
  Status update(double dt, const VehicleSetpoint& setpoint, const VehicleBody& body, ControllerOutput* output);

  /// The longest update period [s] at which the level hold, its PD held over each update, still settles (from
  /// configure()'s vehicle and gains; infinite without a hold): 0.104 s for the default BlueROV2 Heavy.
  double levelStepLimit() const { return level_step_limit_; }

  /// The integral terms [N; N m]: the translational one in world axes (x, y, z; kept there, so that what it
  /// cancels, fixed in the world, stays cancelled as the vehicle turns; each update acts with its part on each
  /// body axis, surge, sway and heave, held within that axis's integral_limit), then yaw's.
  const Vector4& integral() const { return integral_; }
  /// Restarts the integrals at 0.
  void reset() { integral_.setZero(); }

  /// The heading [rad] in (-pi, pi] of an attitude: the angle of its x axis projected on the world's x-y plane.
  static double yawOf(const Eigen::Quaterniond& attitude);

 private:
  /// The world error with its horizontal part's length held within reach_[0] and its vertical part within
  /// reach_[1].
  Eigen::Vector3d boundedError(const Eigen::Vector3d& world_error) const;

  /// The reach is this many times the error at which the proportional term alone meets the thrust limit.
  static constexpr double kReachFactor = 2.0;
  /// Horizontal and vertical reach [m]: kReachFactor times the larger of limit / kp in surge and sway, and in heave.
  static Eigen::Vector2d reachOf(const Vector4& limit, const ControllerGains& gains);

  ControllerGains gains_;
  Vector4 limit_{113.7, 113.7, 160.8, 30.4};         ///< Thrust limits of the controlled axes [N; N m].
  Eigen::Vector2d level_limit_{35.1, 19.3};          ///< Roll and pitch thrust limits [N m].
  Eigen::Vector2d reach_ = reachOf(limit_, gains_);  ///< Horizontal, vertical reach [m].
  double level_step_limit_ =
      0.1036;  ///< levelStepLimit() [s], the default BlueROV2 Heavy's (roll's), as configure() gives it
  Vector4 integral_ = Vector4::Zero();
};

}  // namespace rov_tether
