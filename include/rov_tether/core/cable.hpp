#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "rov_tether/core/line_mass.hpp"

namespace rov_tether
{

/// A point in the world frame, z up (REP 103) [m].
using Position = Eigen::Vector3d;
/// A force in the world frame [N].
using Force = Eigen::Vector3d;

/**
 * A cable whose material is not the same all along it (sections, attachments: CableSections::load), per
 * segment and per particle, indexed like the Cable's arrays. Empty for a uniform cable, whose material is its
 * parameters': every reader keeps that case's arithmetic as it was.
 */
struct CableLoading
{
  // Per segment j (joining particles j and j + 1).
  std::vector<double> mass_along;         ///< Mass per metre along the cable [kg/m].
  std::vector<double> mass_across;        ///< Mass per metre across it, added mass included [kg/m].
  std::vector<double> weight;             ///< Net weight in water per metre, down positive [N/m].
  std::vector<double> normal_drag;        ///< 1/2 rho C_dn d: drag across per metre per (m/s)^2 [kg/m^2].
  std::vector<double> tangential_drag;    ///< 1/2 rho C_dt pi d: drag along per metre per (m/s)^2 [kg/m^2].
  std::vector<double> axial_stiffness;    ///< EA [N].
  std::vector<double> axial_damping;      ///< BA [N s].
  std::vector<double> bending_stiffness;  ///< EI [N m^2].
  // Per particle i: the attachments' shares (one between two particles is split by its distance to each).
  std::vector<double> point_mass;   ///< Their own mass [kg].
  std::vector<double> point_added;  ///< Their added mass [kg].
  std::vector<double> point_force;  ///< Net buoyancy in water, up positive [N].
  std::vector<double> point_drag;   ///< 1/2 rho C_d A [kg/m].
  // With a water surface (water_surface_z; empty without one: all submerged). WaterSurface::update sets them.
  std::vector<double> submerged;  ///< Per segment: the share of it below the surface [-].
  std::vector<double> wet;        ///< Per particle: 1 below the surface, 0 above [-].

  /// Standard gravity, for the weight in air above the surface [m/s^2].
  static constexpr double kGravity = 9.80665;

  /// True when some segment's mass across differs from its mass along (added mass).
  bool anisotropic = false;

  bool empty() const { return mass_along.empty(); }
  /// Share of segment j under water [-].
  double submergedShare(std::size_t j) const { return submerged.empty() ? 1.0 : submerged[j]; }
  /// Whether particle i is under water: 1 or 0 [-].
  double wetness(std::size_t i) const { return wet.empty() ? 1.0 : wet[i]; }
  /// Weight per metre of segment j, down positive: in water below the surface, in air above it, in proportion
  /// when it crosses [N/m].
  double segmentWeight(std::size_t j) const
  {
    if (submerged.empty())
    {
      return weight[j];
    }
    const double f = submerged[j];
    return f * weight[j] + (1.0 - f) * mass_along[j] * kGravity;
  }
  /// Mass per metre of segment j across the cable: the added mass only for its share under water [kg/m].
  double segmentMassAcross(std::size_t j) const
  {
    return submerged.empty() ? mass_across[j] : mass_along[j] + submerged[j] * (mass_across[j] - mass_along[j]);
  }
  /// The attachments' force on particle i, up positive: their net buoyancy in water, their weight in air [N].
  double pointForce(std::size_t i) const { return wetness(i) > 0.0 ? point_force[i] : -point_mass[i] * kGravity; }
  /// Net weight of particle i's share: half of each neighbouring segment less its attachments' buoyancy, down
  /// positive [N]; `rest` the cable's segment lengths, `first` the spool outlet.
  double particleWeight(std::size_t i, const std::vector<double>& rest, std::size_t first) const
  {
    const double left = i > first ? segmentWeight(i - 1) * rest[i - 1] : 0.0;
    const double right = i < rest.size() ? segmentWeight(i) * rest[i] : 0.0;
    return 0.5 * (left + right) - pointForce(i);
  }
};

/**
 * The particles of the whole cable (deployed or on the spool) as structure-of-arrays, so that the solver
 * loops are contiguous and vectorise. Nothing else: forces, solvers, the spool and the vehicle act on it.
 *
 * Particle `first` is the spool outlet (pinned); particles [0, first) are still on the spool and are
 * never touched; particles [first, size()) are deployed. The last particle is the vehicle attachment
 * (pinned) when a vehicle is attached, otherwise a free end. Segment j joins particles j and j+1;
 * bending constraint j joins particles j and j+2.
 */
struct Cable
{
  std::vector<double> x, y, z;     ///< Positions [m].
  std::vector<double> px, py, pz;  ///< Positions one step ago [m].
  std::vector<double> inv_mass;    ///< Inverse particle mass across the cable [1/kg], 0 = pinned.
  /// Inverse particle mass along the cable [1/kg], 0 = pinned: larger than inv_mass when the water adds mass
  /// across the cable only (then `anisotropic`); the same otherwise.
  std::vector<double> inv_mass_along;
  /// Unit tangent at each particle (from its neighbours), the direction inv_mass_along applies in; kept only
  /// while `anisotropic` (Tether::subStep sets it at the start of every sub-step).
  std::vector<double> tx, ty, tz;
  bool anisotropic = false;
  std::vector<double> rest;            ///< Rest length of segment j [m] (size - 1 entries).
  std::vector<double> stretch_weight;  ///< 1 / (w_j + w_{j+1}) [kg], 0 when both are pinned.
  std::vector<double> bend_rest;       ///< Rest distance of bending constraint j: rest_j + rest_{j+1} [m].
  std::vector<double> bend_weight;     ///< 1 / (w_j + w_{j+2}) [kg], 0 when both are pinned.
  std::size_t first = 0;               ///< Index of the spool outlet particle.
  CableLoading loading;                ///< Material per segment and particle when not uniform.
  /// Particles whose mass, or whose constraints' rest length or weight, changed since a solver last
  /// read them: [dirty_begin, dirty_end). Solvers that keep copies refresh only this range.
  std::size_t dirty_begin = 0;
  std::size_t dirty_end = static_cast<std::size_t>(-1);

  /// Marks particles [begin, end) and the constraints starting there as changed.
  void markDirty(std::size_t begin, std::size_t end)
  {
    if (dirty_begin >= dirty_end)
    {
      dirty_begin = begin, dirty_end = end;
    }
    else
    {
      dirty_begin = std::min(dirty_begin, begin), dirty_end = std::max(dirty_end, end);
    }
  }

  /// Number of particles (deployed and on the spool).
  std::size_t size() const { return x.size(); }
  /// Allocates every array for `particles` particles, all zero.
  void resize(std::size_t particles);
  /// Position of particle i [m].
  Position position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  /// Sets position and previous position of particle i (zero velocity) [m].
  void place(std::size_t i, const Position& p);
  /// Sets particle i at p, having moved by `moved` over the step: its previous position p - moved (a
  /// kinematic end, so a dashpot reads its motion in the strain rate) [m].
  void placeMoving(std::size_t i, const Position& p, const Position& moved);
  /// Geometric strain |x_{j+1} - x_j| / rest_j - 1 of segment j [-].
  double strain(std::size_t j) const { return (position(j + 1) - position(j)).norm() / rest[j] - 1.0; }
  /// Length of segment j at the step's start, from the previous positions px, py, pz [m].
  double startLength(std::size_t j) const
  {
    const double dx = px[j + 1] - px[j], dy = py[j + 1] - py[j], dz = pz[j + 1] - pz[j];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  /// Unit vector from particle a to particle b (zero when they coincide).
  Position direction(std::size_t a, std::size_t b) const;
  /// Recomputes the lumped masses of deployed particles [lo, hi] (half of each neighbouring segment at
  /// `mass` per metre; the spool outlet, and the last particle when `last_pinned`, get none) and the
  /// weights and bending rest lengths of the constraints they take part in; marks them dirty.
  void updateMasses(std::size_t lo, std::size_t hi, const LineMass& mass, bool last_pinned);
  /// Gives particle i the inverse mass w [1/kg] in every direction (0 pins it) and refreshes the weights of the
  /// constraints it takes part in; marks them dirty. For a particle whose mass is not the cable's own (a
  /// dynamic vehicle's attachment point, VehicleCoupling).
  void setInverseMass(std::size_t i, double w);
  /// Sets the unit tangents of the deployed particles from their neighbours (one-sided at the ends).
  void updateTangents();
};

}  // namespace rov_tether
