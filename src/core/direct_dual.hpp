#pragma once
// The direct solver's dual path: Newton on the multipliers, each iteration an exact tridiagonal solve
// (J W J^T + alpha) dlambda = C - alpha lambda for a primal-dual active set of the one-sided segments, the
// particles moving by W J^T dlambda. See direct_solver.hpp.
#include <cstddef>
#include <vector>

#include "direct_workspace.hpp"
#include "rov_tether/core/direct_solver.hpp"

namespace rov_tether
{

class DualNewton
{
 public:
  DualNewton(DirectWorkspace& workspace, DirectSolver::LinearSolve linear) : ws_(workspace), linear_(linear) {}
  /// Sizes its buffers for a cable of n particles (once: pay-out never allocates).
  void reserve(std::size_t n);
  /// The first iterate: lambda = the last step's multipliers, the positions x~ + W J^T lambda. `lambda`
  /// points at segment first's multiplier (zero on entry).
  void warmStart(Cable& cable, double* lambda);
  /// Newton iterations until every residual is below `tolerance` or `max_iterations` are spent, or until an
  /// iteration fails to lower the residual (that one is undone: the primal path takes over).
  using Result = NewtonResult;
  Result solve(Cable& cable, double* lambda, double tolerance, int max_iterations);

 private:
  /// The active set at the current iterate (into the workspace's on()) and the largest relative residual.
  double residual(const Cable& cable, const double* lambda);
  /// One Newton iteration: the active-set rounds on one linearisation (counted into `rounds`), then the step.
  void step(Cable& cable, double* lambda, int* rounds);
  /// Solves the tridiagonal system for the active set into dlambda(); false if it is not definite.
  bool solveRows();
  /// The same with row 0 (the spool segment) on the drum's law, met exactly (two solves).
  bool solveWithDrum(const double* lambda);
  /// Fills extra_mobility_ (w_along - w_across of each particle) for a cable with added mass.
  void anisotropicMobility(const Cable& cable);
  /// Moves the particles by W J^T dlambda and adds dlambda to the multipliers.
  void apply(Cable& cable, double* lambda);

  DirectWorkspace& ws_;
  DirectSolver::LinearSolve linear_;
  std::vector<double> extra_mobility_;            ///< w_along - w_across of particle l (added mass) [1/kg].
  std::vector<double> response_, zeros_;          ///< With the drum: the solve with dlambda_0 = 0; zeros.
  std::vector<double> diag_, off_;                ///< The tridiagonal system.
  std::vector<double> diag_active_, rhs_active_;  ///< Every row as if active.
  std::vector<double> saved_lambda_;              ///< The multipliers before an iteration (undone if no progress).
  // Padded with a zero before row 0 and after row m - 1 (the accessors point at row 0): each row's coupling
  // to the next, the multipliers, and the step dlambda (the system's right-hand side, then its solution).
  std::vector<double> coupling_, padded_lambda_, dual_step_;
  double* coupling() { return coupling_.data() + 1; }
  double* paddedLambda() { return padded_lambda_.data() + 1; }
  double* dlambda() { return dual_step_.data() + 1; }
};

}  // namespace rov_tether
