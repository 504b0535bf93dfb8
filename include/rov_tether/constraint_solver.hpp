#pragma once

#include <memory>

#include "rov_tether/cable_state.hpp"
#include "rov_tether/tether_params.hpp"

namespace rov_tether
{

/// What a solver needs to know about one step.
struct SolverSettings
{
  int iterations = 10;            ///< Sweeps over all constraints [-].
  bool bending = true;            ///< Project the (i, i+2) bending constraints.
  double time_step = 0.005;       ///< Step the constraints are solved for [s].
  double axial_stiffness = 1e5;   ///< EA [N]; unused by the pbd solvers.
};

/**
 * Projects the distance and bending constraints of the deployed particles [first, size()).
 *
 * Implementations reset and accumulate CableState::stretch_lambda and bend_lambda (the constraint
 * multipliers in kg m, force = lambda / dt^2) so that tension can be read after the step whatever the
 * method. Later methods (XPBD with compliance, force-based chains) implement the same interface.
 */
class ConstraintSolver
{
 public:
  virtual ~ConstraintSolver() = default;
  /// Projects the constraints once per step; must not allocate.
  virtual void solve(CableState& state, const SolverSettings& settings) = 0;
};

/// The paper's Figure 2 (stretch sweep then (i, i+2) bending sweep, `iterations` times) in red-black
/// order: even segments, odd segments, then bending constraints in four interleaved sets. Constraints
/// of one set share no particle, so each set is one vectorisable loop.
class PbdSolver : public ConstraintSolver
{
 public:
  void solve(CableState& state, const SolverSettings& settings) override;
};

/// The paper's Figure 2 in its literal order (segment 0, 1, 2, ... then bending 0, 1, ...). Kept as the
/// reference for the red-black solver's convergence and speed.
class SequentialPbdSolver : public ConstraintSolver
{
 public:
  void solve(CableState& state, const SolverSettings& settings) override;
};

/// Creates the solver for `type`.
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type);

}  // namespace rov_tether
