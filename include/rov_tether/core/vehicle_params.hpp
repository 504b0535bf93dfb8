#pragma once
// The parameters of a vehicle's rigid body in the water (VehicleBody): mass, inertia, centres of gravity and
// buoyancy, added mass, damping and thrust limits, in the body frame x forward, y left, z up (REP 103).
// The defaults are the BlueROV2 Heavy of von Benzon et al. 2022 (docs/references.md); a file per vehicle
// (config/vehicles/) is read by spec::readVehicleParams.

#include <Eigen/Core>
#include <string>

#include "rov_tether/core/status.hpp"

namespace rov_tether
{

/// Six generalized components in Fossen's order: surge, sway, heave (x, y, z), roll, pitch, yaw.
using Vector6 = Eigen::Matrix<double, 6, 1>;
/// A body-frame wrench [Fx, Fy, Fz, Mx, My, Mz] [N, N m].
using Wrench = Vector6;

/**
 * A vehicle's rigid-body and hydrodynamic parameters (Fossen, Handbook of Marine Craft Hydrodynamics and
 * Motion Control, 2011, ch. 3-8) in the body frame x forward, y left, z up, with its origin at the
 * vehicle's reference point (the centre the pose names).
 *
 * Published figures are usually identified in Fossen's NED body frame (x forward, y starboard, z down). It is
 * the FLU frame turned half a turn about x: T = diag(1, -1, -1) on vectors, and T6 = diag(1, -1, -1, 1, -1,
 * -1) on six-vectors. So a matrix A_flu = T6 A_ned T6: diagonal terms (masses, inertias, added masses,
 * damping) keep their values and sign; an off-diagonal term coupling x or roll with y, z, pitch or yaw flips
 * sign; a position's y and z flip sign (a centre of buoyancy 0.01 m above the centre of gravity is z_b =
 * -0.01 in NED, +0.01 here). Weight acts along -z and buoyancy along +z of the world (z up).
 * Damping and added-mass coefficients are given as positive magnitudes: linear_damping[0] is -X_u,
 * quadratic_damping[0] is -X_{u|u|}, added_mass[0] is -X_{u dot} in Fossen's notation.
 */
struct VehicleParams
{
  /// Dry mass m [kg].
  double mass = 13.5;
  /// Displaced volume V [m^3]: buoyancy rho g V.
  double displaced_volume = 0.0134;
  /// Density of the water rho [kg/m^3] (fresh water, as re-implementations of the paper take it).
  double water_density = 1000.0;
  /// Gravity g [m/s^2].
  double gravity = 9.81;
  /// Principal moments of inertia Ix, Iy, Iz about the centre of gravity, body axes [kg m^2].
  Eigen::Vector3d inertia{0.26, 0.23, 0.37};
  /// Centre of gravity r_G in the body frame [m].
  Eigen::Vector3d center_of_gravity{0.0, 0.0, 0.0};
  /// Centre of buoyancy r_B in the body frame [m].
  Eigen::Vector3d center_of_buoyancy{0.0, 0.0, 0.01};
  /// Diagonal added mass -X_udot, -Y_vdot, -Z_wdot [kg], -K_pdot, -M_qdot, -N_rdot [kg m^2].
  Vector6 added_mass = (Vector6() << 6.36, 7.12, 18.68, 0.189, 0.135, 0.222).finished();
  /// Linear damping -X_u, -Y_v, -Z_w [N s/m], -K_p, -M_q, -N_r [N m s/rad].
  Vector6 linear_damping = (Vector6() << 13.7, 0.0, 33.0, 0.0, 0.8, 0.0).finished();
  /// Quadratic damping -X_u|u|, -Y_v|v|, -Z_w|w| [N s^2/m^2], -K_p|p|, -M_q|q|, -N_r|r| [N m s^2/rad^2].
  Vector6 quadratic_damping = (Vector6() << 141.0, 217.0, 190.0, 1.19, 0.47, 1.5).finished();
  /// Largest thrust per axis, either sign [N, N m]: a command beyond it is held at it (and reported).
  /// BlueROV2 Heavy: 4.1 kgf (40.2 N, the T200's reverse thrust at 16 V) per thruster, summed over the
  /// thrusters' components on each axis (config/vehicles/bluerov2_heavy.yaml says how).
  Vector6 thrust_limit = (Vector6() << 113.7, 113.7, 160.8, 35.1, 19.3, 30.4).finished();
  /// Outer size: length (x), width (y), height (z) [m]: the box the node draws in rviz, centred on the body origin;
  /// and with a water surface, its height is the hull's, centred on the centre of buoyancy, over which the hull
  /// comes out of the water (VehicleBody::submergedShare).
  /// BlueROV2 Heavy: 457 x 575 x 254 mm (Blue Robotics' BlueROV2 technical specifications, Heavy configuration;
  /// config/vehicles/bluerov2_heavy.yaml).
  Eigen::Vector3d size{0.457, 0.575, 0.254};

  /// Checks every field: finite; mass, water_density, inertia > 0; displaced_volume, gravity, added mass,
  /// damping and thrust limits >= 0; size > 0; the principal moments satisfy the triangle inequality (a rigid body's
  /// do); centres within kMaxOffset of the origin. Returns the first problem, naming the field and value.
  Status validate() const;

  /// Weight m g [N] and buoyancy rho g V [N].
  double weight() const { return mass * gravity; }
  double buoyancy() const { return water_density * gravity * displaced_volume; }

  /// Largest distance of a centre from the body origin [m].
  static constexpr double kMaxOffset = 100.0;
};

/// "" when `vehicle`'s water_density is the tether's `water_density` [kg/m^3]; otherwise a warning with both and the
/// buoyancy the vehicle would have in the tether's water: a vehicle file identified in fresh water (the BlueROV2
/// Heavy's) on a tether in sea water floats in other water than its cable, 2.5% of its buoyancy apart.
std::string waterMismatch(const VehicleParams& vehicle, double water_density);

}  // namespace rov_tether
