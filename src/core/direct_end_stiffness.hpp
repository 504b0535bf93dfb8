#pragma once
// The direct solver's linearisation at a pinned last particle (a kinematic vehicle end): how the last step's
// pull on it changes with its position, the rest of the chain answering through the step's Newton system.
// See end_linearisation.hpp (what it means) and docs/model.md ("A kinematic end's linearisation for external
// simulators"). Not installed: DirectSolver's front (direct_solver.cpp) owns one.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "direct_primal.hpp"
#include "direct_workspace.hpp"

namespace rov_tether
{

class EndStiffness
{
 public:
  explicit EndStiffness(DirectSolver::LinearSolve linear) : primal_(workspace_, linear) {}
  EndStiffness(const EndStiffness&) = delete;
  EndStiffness& operator=(const EndStiffness&) = delete;

  /// K = dF/dx_e [N/m] of the pull F = -lambda_e n_e / h^2 of the last segment on the pinned last particle
  /// x_e, for the step of `settings` (its time_step h) that left `cable` and `multipliers`: the Schur
  /// complement of the step's Hessian onto x_e, K = -(B - B Y) / h^2 with B the last segment's block and Y
  /// the free particles' answer dx_f/dx_e = -H_ff^-1 H_fe (three solves with one factorisation). Zero, and
  /// *taut false, when the last segment carries no tension. False when the Hessian is not positive definite.
  /// `horizon` [s] > h: the same at the same state for an implicit step of that length instead of h (the
  /// particles' inertia M / horizon^2, the pull and its multipliers unchanged as forces): what the chain
  /// answers over a longer time, tending to the static stiffness. Its own workspace: the solver's warm start
  /// for the next step is not touched. Allocation-free once sized.
  bool compute(const Cable& cable, const Multipliers& multipliers, const SolverSettings& settings, double horizon,
               Eigen::Matrix3d* stiffness, bool* taut);

 private:
  DirectWorkspace workspace_;
  PrimalNewton primal_;
  Multipliers scratch_;          ///< What DirectWorkspace::begin clears (the step's own are not touched).
  std::vector<double> columns_;  ///< The three right-hand sides, then dx_f/dx_e by columns.
  std::vector<double> scaled_;   ///< The step's multipliers as the horizon's step would carry them.
};

}  // namespace rov_tether
