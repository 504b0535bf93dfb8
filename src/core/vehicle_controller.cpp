#include "rov_tether/core/vehicle_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace rov_tether
{
namespace
{

constexpr const char* kAxisNames[4] = {"surge", "sway", "heave", "yaw"};
// Bit of each controlled axis in ThrustUsed's numbering (0 surge, 1 sway, 2 heave, 5 yaw), and its wrench row.
constexpr int kWrenchRow[4] = {0, 1, 2, 5};
constexpr double kPi = 3.14159265358979323846;

std::string number(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

// "" or "<field>[<axis>]: must be <rule> (got <value>)" for the first axis breaking the rule.
template <typename Rule>
std::string checkEach(const char* field, const Vector4& values, const char* rule, Rule ok)
{
  for (int i = 0; i < 4; ++i)
  {
    if (!std::isfinite(values[i]))
    {
      return std::string(field) + "[" + kAxisNames[i] + "]: must be finite (got " + number(values[i]) + ")";
    }
    if (!ok(values[i]))
    {
      return std::string(field) + "[" + kAxisNames[i] + "]: must be " + rule + " (got " + number(values[i]) + ")";
    }
  }
  return "";
}

// "" or "<field>[roll|pitch]: must be >= 0 (got <value>)" / "must be finite".
std::string checkLevel(const char* field, const Eigen::Vector2d& values)
{
  const char* names[2] = {"roll", "pitch"};
  for (int j = 0; j < 2; ++j)
  {
    if (!std::isfinite(values[j]) || !(values[j] >= 0.0))
    {
      return std::string(field) + "[" + names[j] + "]: must be finite and >= 0 (got " + number(values[j]) + ")";
    }
  }
  return "";
}

// Mass with added mass m' and linear damping d of the controlled axis i of `vehicle` (ControllerGains).
double effectiveMass(const VehicleParams& vehicle, int i)
{
  return (i < 3 ? vehicle.mass : vehicle.inertia.z()) + vehicle.added_mass[kWrenchRow[i]];
}

double linearDamping(const VehicleParams& vehicle, int i) { return vehicle.linear_damping[kWrenchRow[i]]; }

/// Roll (j 0) or pitch (j 1) inertia with its added inertia, I' [kg m^2]: the level hold's plant.
double levelInertia(const VehicleParams& vehicle, int j) { return vehicle.inertia[j] + vehicle.added_mass[3 + j]; }

}  // namespace

Status ControllerDesign::validate() const
{
  const std::string bad = checkEach("bandwidth", bandwidth, "> 0 rad/s", [](double x) { return x > 0.0; });
  if (!bad.empty())
  {
    return Status::error("controller design: " + bad);
  }
  if (!std::isfinite(damping_ratio) || !(damping_ratio > 0.0))
  {
    return Status::error("controller design: damping_ratio: must be finite and > 0 (got " + number(damping_ratio) +
                         ")");
  }
  if (!std::isfinite(level_bandwidth) || !(level_bandwidth >= 0.0))
  {
    return Status::error("controller design: level_bandwidth: must be finite and >= 0 (got " + number(level_bandwidth) +
                         ")");
  }
  if (!std::isfinite(integral_ratio) || !(integral_ratio >= 0.0))
  {
    return Status::error("controller design: integral_ratio: must be finite and >= 0 (got " + number(integral_ratio) +
                         ")");
  }
  return Status::success();
}

Status ControllerGains::validate() const
{
  const auto positive = [](double x) { return x > 0.0; };
  const auto nonNegative = [](double x) { return x >= 0.0; };
  const std::string problems[] = {
      checkEach("proportional", proportional, "> 0", positive),
      checkEach("integral", integral, ">= 0", nonNegative),
      checkEach("derivative", derivative, ">= 0", nonNegative),
      checkEach("integral_limit", integral_limit, ">= 0", nonNegative),
      checkLevel("level_proportional", level_proportional),
      checkLevel("level_derivative", level_derivative),
  };
  for (const auto& problem : problems)
  {
    if (!problem.empty())
    {
      return Status::error("controller: " + problem);
    }
  }
  return Status::success();
}

Status ControllerGains::design(const VehicleParams& vehicle, const ControllerDesign& design, ControllerGains* gains)
{
  const Status vehicle_ok = vehicle.validate();
  if (!vehicle_ok)
  {
    return vehicle_ok;
  }
  const Status design_ok = design.validate();
  if (!design_ok)
  {
    return design_ok;
  }
  ControllerGains designed;
  for (int i = 0; i < 4; ++i)
  {
    const double m = effectiveMass(vehicle, i);
    const double w = design.bandwidth[i];
    const double wi = design.integral_ratio * w;
    const double z = design.damping_ratio;
    designed.proportional[i] = m * (w * w + 2.0 * z * w * wi);
    designed.integral[i] = m * w * w * wi;
    designed.derivative[i] = m * (2.0 * z * w + wi) - linearDamping(vehicle, i);
    if (designed.derivative[i] < 0.0)
    {
      return Status::error(std::string("controller design: ") + kAxisNames[i] + ": the vehicle's linear damping " +
                           number(linearDamping(vehicle, i)) +
                           " exceeds m' (2 zeta omega + omega_i) = " + number(m * (2.0 * z * w + wi)) +
                           " (a negative derivative gain): ask for a higher bandwidth");
    }
    designed.integral_limit[i] = vehicle.thrust_limit[kWrenchRow[i]];
  }
  designed.anti_windup = true;
  for (int j = 0; j < 2; ++j)  // the level hold: roll (row 3), pitch (row 4)
  {
    const double w = design.level_bandwidth;
    const double inertia = levelInertia(vehicle, j);
    designed.level_proportional[j] = inertia * w * w;
    // Critically damped whatever damping_ratio the translation asks: the hold's margin at a coarse update period
    // is thin (levelStepLimit()), and a larger ratio would shrink it.
    designed.level_derivative[j] = std::max(0.0, 2.0 * w * inertia - vehicle.linear_damping[3 + j]);
  }
  *gains = designed;
  return Status::success();
}

Status VehicleController::configure(const VehicleParams& vehicle, const ControllerGains& gains)
{
  const Status vehicle_ok = vehicle.validate();
  if (!vehicle_ok)
  {
    return vehicle_ok;
  }
  const Status gains_ok = gains.validate();
  if (!gains_ok)
  {
    return gains_ok;
  }
  for (int i = 0; i < 4; ++i)
  {
    const double m = effectiveMass(vehicle, i);
    const double d = linearDamping(vehicle, i);
    // Routh-Hurwitz for m s^3 + (d + kd) s^2 + kp s + ki with every coefficient > 0 (kp > 0 checked; ki = 0
    // leaves a PD loop, stable when d + kd > 0).
    const double damping = d + gains.derivative[i];
    const bool stable =
        gains.integral[i] == 0.0 ? damping > 0.0 : damping * gains.proportional[i] > m * gains.integral[i];
    if (!stable)
    {
      return Status::error(
          std::string("controller: ") + kAxisNames[i] + ": the loop linearised at rest is unstable: (d + kd) kp = " +
          number(damping * gains.proportional[i]) + " must exceed m' ki = " + number(m * gains.integral[i]) + " (d " +
          number(d) + ", kd " + number(gains.derivative[i]) + ", kp " + number(gains.proportional[i]) + ", ki " +
          number(gains.integral[i]) + ", m' " + number(m) + "; d + kd > 0 without ki)");
    }
  }
  gains_ = gains;
  for (int i = 0; i < 4; ++i)
  {
    limit_[i] = vehicle.thrust_limit[kWrenchRow[i]];
  }
  level_limit_ = vehicle.thrust_limit.segment<2>(3);
  reach_ = reachOf(limit_, gains);
  // The level hold's PD acts on the state at the update's start and is held for dt: per axis the discrete loop
  // I' x'' = -kp x - kd x' (the vehicle's own damping is implicit in its step) is stable while
  // (kp / I') dt^2 + 2 (kd / I') dt < 4, so up to dt = (-b + sqrt(b^2 + 4 a)) / a, a = kp / I', b = kd / I'.
  level_step_limit_ = std::numeric_limits<double>::infinity();
  for (int j = 0; j < 2; ++j)
  {
    const double inertia = levelInertia(vehicle, j);
    const double a = gains.level_proportional[j] / inertia;
    const double b = gains.level_derivative[j] / inertia;
    if (a > 0.0)
    {
      level_step_limit_ = std::min(level_step_limit_, (-b + std::sqrt(b * b + 4.0 * a)) / a);
    }
    else if (b > 0.0)
    {
      level_step_limit_ = std::min(level_step_limit_, 2.0 / b);
    }
  }
  integral_.setZero();
  return Status::success();
}

Eigen::Vector3d VehicleController::boundedError(const Eigen::Vector3d& world_error) const
{
  // Horizontal and vertical parts bounded apart, each keeping its direction, so a far setpoint neither takes
  // the depth's authority nor, rotated by a small tilt, asks for the heave limit.
  Eigen::Vector3d bounded = world_error;
  const double horizontal = std::hypot(world_error.x(), world_error.y());  // no overflow for a huge error
  if (horizontal > reach_[0])
  {
    bounded.head<2>() *= reach_[0] / horizontal;
  }
  bounded.z() = std::clamp(world_error.z(), -reach_[1], reach_[1]);
  return bounded;
}

Eigen::Vector2d VehicleController::reachOf(const Vector4& limit, const ControllerGains& gains)
{
  return Eigen::Vector2d(kReachFactor * std::max(limit[0] / gains.proportional[0], limit[1] / gains.proportional[1]),
                         kReachFactor * limit[2] / gains.proportional[2]);
}

double VehicleController::yawOf(const Eigen::Quaterniond& attitude)
{
  const Eigen::Vector3d forward = attitude * Eigen::Vector3d::UnitX();
  return std::atan2(forward.y(), forward.x());
}

Status VehicleController::update(double dt, const VehicleSetpoint& setpoint, const VehicleBody& body,
                                 ControllerOutput* output)
{
  if (!std::isfinite(dt) || !(dt > 0.0))
  {
    return Status::error("vehicle controller: dt must be finite and > 0 (got " + number(dt) + ")");
  }
  if (!setpoint.position.allFinite() || !std::isfinite(setpoint.yaw) || !setpoint.velocity.allFinite() ||
      !std::isfinite(setpoint.yaw_rate))
  {
    return Status::error("vehicle controller: the setpoint (position, yaw, velocity, yaw rate) must be finite");
  }
  const Eigen::Quaterniond to_body = body.attitude().conjugate();
  const Eigen::Vector3d position_error = to_body * boundedError(setpoint.position - body.position());
  const Eigen::Vector3d velocity_error = to_body * setpoint.velocity - body.velocity().head<3>();
  // std::remainder(x, 2 pi) is x - 2 pi n with n the nearest integer: the error in [-pi, pi], the short way.
  const double yaw_error = std::remainder(setpoint.yaw - yawOf(body.attitude()), 2.0 * kPi);
  const double yaw_rate_error = setpoint.yaw_rate - body.velocity()[5];

  const Vector4 error(position_error.x(), position_error.y(), position_error.z(), yaw_error);
  const Vector4 rate_error(velocity_error.x(), velocity_error.y(), velocity_error.z(), yaw_rate_error);

  // The translational integral is kept in world axes: what it cancels (a current, a tether's pull, a net
  // buoyancy) is fixed in the world, and stays so while the vehicle turns. Each update takes it into the body's
  // axes, where each axis's term acts held within its integral_limit and advances, and turns it back.
  Vector4 integral;
  integral << to_body * integral_.head<3>(), integral_[3];
  ControllerOutput result;
  result.level_step_too_long = dt > level_step_limit_;
  // Thrusters out of the water push nothing: the body gives the hull's wet share of the thrust asked, held
  // within the limit (VehicleBody::step). Partly in, asking more still pushes harder, up to the limit, and the
  // integral is what asks it; wholly out, no ask moves the body, and integrating would only wind up.
  const bool dry = !(body.submergedShare() > 0.0);
  for (int i = 0; i < 4; ++i)
  {
    const double cap = gains_.integral_limit[i];
    // A turn can put more on an axis than its limit (what two axes held, on one): the term acts held, the rest kept.
    const double term = integral[i] > cap ? cap : (integral[i] < -cap ? -cap : integral[i]);
    const auto bit = static_cast<std::uint8_t>(1u << kWrenchRow[i]);
    if (term != integral[i])
    {
      result.integral_held_axes |= bit;
    }
    const double wanted = gains_.proportional[i] * error[i] + term + gains_.derivative[i] * rate_error[i];
    const double limit = limit_[i];
    const double held = wanted > limit ? limit : (wanted < -limit ? -limit : wanted);
    if (held != wanted)
    {
      result.saturated_axes |= bit;
    }
    result.thrust[kWrenchRow[i]] = held;

    // Conditional integration: not while held at the limit (or out of the water) with the error pushing
    // further out.
    const bool winding = (held != wanted || dry) && error[i] * wanted > 0.0;
    const double before = integral[i];
    const double after = !gains_.anti_windup || !winding ? before + gains_.integral[i] * error[i] * dt : before;
    // The integral limit: integrating never takes an axis beyond it (one already beyond by a turn stays as it is).
    if (std::abs(after) > cap && std::abs(after) > std::abs(before))
    {
      integral[i] = std::abs(before) > cap ? before : std::copysign(cap, after);
      result.integral_held_axes |= bit;
    }
    else
    {
      integral[i] = after;
    }
  }
  integral_ << body.attitude() * integral.head<3>(), integral[3];
  // Turns cannot pile it up either: horizontally no longer than the surge and sway limits' diagonal, beyond which
  // no heading could use it.
  const double horizontal = std::hypot(integral_[0], integral_[1]);
  const double widest = std::hypot(gains_.integral_limit[0], gains_.integral_limit[1]);
  if (horizontal > widest)
  {
    integral_.head<2>() *= widest / horizontal;
  }
  // The level hold: the torque that turns the body's z axis towards the world's, z_b x up = [-up_y, up_x, 0].
  const Eigen::Vector3d up = to_body * Eigen::Vector3d::UnitZ();
  const double tilt[2] = {-up.y(), up.x()};
  for (int j = 0; j < 2; ++j)
  {
    const double wanted = gains_.level_proportional[j] * tilt[j] - gains_.level_derivative[j] * body.velocity()[3 + j];
    const double limit = level_limit_[j];
    const double held = wanted > limit ? limit : (wanted < -limit ? -limit : wanted);
    if (held != wanted)
    {
      result.saturated_axes |= static_cast<std::uint8_t>(1u << (3 + j));
    }
    result.thrust[3 + j] = held;
  }
  if (output != nullptr)
  {
    *output = result;
  }
  return Status::success();
}

}  // namespace rov_tether
