#pragma once

#include <memory>

#include "rov_tether/cable_state.hpp"
#include "rov_tether/tether_params.hpp"

namespace rov_tether
{

/// What a solver needs to know about one step.
struct SolverSettings
{
  int iterations = 10;           ///< Sweeps over all constraints [-].
  bool bending = true;           ///< Project the (i, i+2) bending constraints.
  double time_step = 0.005;      ///< Step the constraints are solved for [s].
  double axial_stiffness = 1e5;  ///< EA [N]; unused by the pbd solvers.
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

/**
 * The paper's Figure 2 (stretch sweep then (i, i+2) bending sweep, `iterations` times) in red-black
 * order: even segments, odd segments, then bending constraints in four interleaved sets. Constraints
 * of one set share no particle, so each set is one loop without dependencies between iterations.
 *
 * For the loops to be unit-stride (and so vectorise well), each step copies the deployed particles
 * into four blocks by index mod 4: particle l of block r is deployed particle 4 l + r. Every set then
 * pairs two blocks element by element. The copies are sized for the whole cable on the first step and
 * reused, so pay-out never allocates.
 */
class PbdSolver : public ConstraintSolver
{
 public:
  void solve(CableState& state, const SolverSettings& settings) override;

 private:
  /// Particle and constraint data of the deployed cable in blocked order (4 blocks of `block_` each).
  std::vector<double> x_, y_, z_, inv_mass_;
  std::vector<double> rest_, weight_, lambda_;                 ///< Stretch constraint l joins l, l + 1.
  std::vector<double> bend_rest_, bend_weight_, bend_lambda_;  ///< Bending constraint l joins l, l + 2.
  std::size_t block_ = 0;
  std::size_t copied_first_ = static_cast<std::size_t>(-1);  ///< Layout of the copied constraint data.
  std::size_t copied_size_ = 0;
  std::size_t copied_block_ = 0;
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
