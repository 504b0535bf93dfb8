#pragma once

#include <Eigen/Core>

#include "rov_tether/core/cable.hpp"

namespace rov_tether
{

/// A velocity in the world frame [m/s] (the same type wherever it is declared).
using Velocity = Eigen::Vector3d;

/**
 * The tether's pull at a kinematic vehicle end, linearised for an external vehicle simulator that applies
 * F = force + stiffness (x - position) + damping (v - velocity) with its own state x, v at its own rate
 * (Tether::vehicleEndLinearisation; docs/model.md, "A kinematic end's linearisation for external simulators").
 *
 * K (stiffness) is the derivative of the last `direct` step's solved pull on the end, F = -lambda_e n_e / h^2
 * (the last segment's multiplier along its direction; vehicleForce() adds the constant weight of the half
 * segment at the end, which K does not see), with respect to where the end was at
 * the step's end, the other particles answering through the step's own equations: their masses M / h^2, the
 * segments' axial stiffness 1 / alpha = EA h^2 / L, the geometric stiffness lambda / |d| (I - n n^T) and the
 * bending joints (EI > 0). With H the step energy's Hessian at the step's solution, B its last segment's block
 * and f the free particles, the free particles answer a move of the end by dx_f = -H_ff^-1 H_fe dx_e, and
 *   K = -(B - B Y) / h^2,   Y = dx_(last free) / dx_e,
 * which for a cable (EI = 0) is minus the Schur complement -(H_ee - H_ef H_ff^-1 H_fe) / h^2: symmetric, and
 * negative semi-definite while every segment pulls (moving the end away pulls it back harder). Its limits: a
 * chain much lighter than its stiffness per step (M / h^2 << EA / L) gives -EA / L_total along the chain and
 * -T / L_total across it; a heavy one, whose particles cannot move within a step, the last segment's
 * -EA / l_last and -T / l_last. With EI > 0 the pull read is still the last segment's (the step's bending
 * force on the pinned end is not in vehicleForce()), so K is its derivative and not exactly symmetric.
 *
 * C (damping) is the pull's derivative with respect to the end's velocity at a fixed end position. Without
 * `axial_damping` it is zero in this model: the end enters the step only through its position at the step's
 * end (pinned there). The prediction x~ of every free particle uses its own velocity (x - x_prev), drag
 * (damping or Morison) acts on the free particles' own velocities (Morison's tangent reads the end's position
 * from the step's start, already past). With `axial_damping` (Kelvin-Voigt, docs/model.md) the last
 * segment's dashpot reads the end's motion over the step (its x_prev, Cable::placeMoving), so the pull has a
 * term in the end's velocity, about -(BA / l_last) n n^T for a taut last segment before the chain answers; it
 * is not computed yet and C is left zero (docs/limitations.md).
 *
 * The linearisation is of the last sub-step (with `substeps` > 1 the earlier sub-steps' answer to the
 * interpolated end is not in it), with the spool segment on its elastic law (a brake drum's give within the
 * step is left out).
 */
struct EndLinearisation
{
  double time = 0.0;                     ///< The physics time of the last step [s].
  Position position = Position::Zero();  ///< x0: the attachment point at that time, world [m].
  /// v0: its velocity over the last sub-step, (x_e(t) - x_e(t - h)) / h [m/s]; zero after an attach, a jump or
  /// a skip (the cable re-laid or held at rest).
  Velocity velocity = Velocity::Zero();
  Force force = Force::Zero();                          ///< F0: the pull on the vehicle (== vehicleForce()) [N].
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero();  ///< K = dF/dx [N/m], world frame.
  /// The step length K is the linearisation of [s]: the sub-step h, or the horizon asked for when longer.
  double horizon = 0.0;
  Eigen::Matrix3d damping = Eigen::Matrix3d::Zero();  ///< C = dF/dv [N s/m], world frame (zero: see above).
  bool taut = false;  ///< False: the end segment carries no tension; K and C are then zero.
};

}  // namespace rov_tether
