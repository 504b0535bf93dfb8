#pragma once

#include <limits>
#include <memory>

#include "rov_tether/cable.hpp"
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
  double bending_stiffness = 0;  ///< EI [N m^2]; xpbd only (0 = no bending resistance).
  double over_relaxation = 1.0;  ///< pbd: each correction times this (successive over-relaxation) [-].
};

/**
 * Projects the distance and bending constraints of the deployed particles [first, size()).
 *
 * Implementations reset and accumulate Cable::stretch_lambda and bend_lambda (the constraint
 * multipliers in kg m, force = lambda / dt^2) so that tension can be read after the step whatever the
 * method. Later methods (XPBD with compliance, force-based chains) implement the same interface.
 */
class ConstraintSolver
{
 public:
  virtual ~ConstraintSolver() = default;
  /// Projects the constraints once per step; must not allocate.
  virtual void solve(Cable& state, const SolverSettings& settings) = 0;
  /// Largest segment strain seen by the last solve() when the method measures it (lumped_mass), else NaN.
  virtual double lastMaxStrain() const { return std::numeric_limits<double>::quiet_NaN(); }
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
  /// Deployed particles up to which the constraints are projected in place, in the same order, without
  /// the blocked copies: for short cables the copies and the many tiny loops cost more than they save.
  static constexpr std::size_t kDirectParticles = 48;

  /// `compliant` makes this XPBD (Macklin, Mueller, Chentanez 2016): each stretch constraint has the
  /// compliance rest / EA and each bending constraint (rest / 2)^3 / EI, so the multipliers converge to
  /// the physical force times dt^2 whatever the iteration count.
  /// `direct_particles`: see kDirectParticles (tests set it to compare both paths).
  explicit PbdSolver(bool compliant = false, std::size_t direct_particles = kDirectParticles)
      : compliant_(compliant), direct_particles_(direct_particles)
  {
  }
  void solve(Cable& state, const SolverSettings& settings) override;

 private:
  void solveDirect(Cable& state, int iterations, bool bending, double stretch_compliance, double bend_compliance,
                   double relax);

  bool compliant_;
  std::size_t direct_particles_;
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
  void solve(Cable& state, const SolverSettings& settings) override;
};

/**
 * A force-based lumped-mass chain: the second half of an explicit Verlet step. The simulation has already
 * moved every particle by inertia, drag and weight (x holds the prediction, px the positions x_n); this adds
 * h^2 F(x_n) / m for the axial spring forces F = EA max(strain, 0) (a cable carries no compression). Stable
 * only for h < dL / sqrt(EA / mu) (TetherParams::criticalStep); the largest strain is reported so that a
 * blow-up is detected. No bending.
 */
class LumpedMassSolver : public ConstraintSolver
{
 public:
  void solve(Cable& state, const SolverSettings& settings) override;
  double lastMaxStrain() const override { return max_strain_; }

 private:
  double max_strain_ = 0.0;
};

/// Creates the solver for `type`.
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type);

}  // namespace rov_tether
