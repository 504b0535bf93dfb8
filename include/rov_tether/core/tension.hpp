#pragma once

#include <cstddef>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{

/// What a tether-management controller reads after a step.
struct TetherSummary
{
  double time = 0.0;                    ///< Simulation time [s].
  double deployed_length = 0.0;         ///< Cable off the spool (sum of rest lengths) [m].
  double tension_spool = 0.0;           ///< Axial force in the segment at the spool [N].
  double tension_vehicle = 0.0;         ///< Axial force in the segment at the vehicle (or free end) [N].
  double max_tension = 0.0;             ///< Largest segment tension [N].
  std::size_t max_tension_segment = 0;  ///< Segment index of max_tension, 0 at the spool.
  double max_strain = 0.0;              ///< Largest geometric strain |d| / rest - 1 [-].
  double mean_strain = 0.0;             ///< Mean absolute geometric strain, the solver's residual stretch [-].
  /// The force the spool outlet receives from the cable [N], world frame: the first segment's pull plus the
  /// weight in water of the half segment lumped at the outlet particle (Tether::spoolForce()).
  Force spool_force = Force::Zero();
  /// The force the vehicle receives [N] (Tether::vehicleForce()); zero with no vehicle attached.
  Force vehicle_force = Force::Zero();
};

/**
 * The tension readout, one for every method: the axial force of each deployed segment (spool first) [N]
 * from the multipliers of the last step of length `step` [s]: the stretch multiplier of the segment and
 * the bending multipliers whose constraints span the same cut, projected on the segment, over step^2.
 * All zero before the first step (step 0).
 */
void segmentTensions(const Cable& cable, const Multipliers& lambda, double step, std::vector<double>& out);

/// Pull of the cable on its last particle (the vehicle attachment) [N], from the same multipliers.
Force endForce(const Cable& cable, const Multipliers& lambda, double step);

/// Pull of the cable on its first deployed particle (the spool outlet) [N], from the same multipliers.
Force startForce(const Cable& cable, const Multipliers& lambda, double step);

/// Deployed length, end tensions, maximum tension and strain from segment tensions already computed.
TetherSummary summarize(const Cable& cable, const std::vector<double>& tensions, double deployed_length, double time);

}  // namespace rov_tether
