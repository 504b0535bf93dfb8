#pragma once

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/contact.hpp"
#include "rov_tether/core/spool_drum.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/// What a solver needs to know about one step.
struct SolverSettings
{
  int iterations = 10;           ///< Sweeps over all constraints [-].
  bool bending = true;           ///< Project the (i, i+2) bending constraints.
  double time_step = 0.005;      ///< Step the constraints are solved for [s].
  double axial_stiffness = 1e5;  ///< EA [N]; unused by the pbd solvers.
  double axial_damping = 0.0;    ///< BA [N s]: Kelvin-Voigt damping of direct, xpbd and lumped_mass (0 = none).
  /// The implicit step's Kelvin-Voigt shift per unit of a segment's stretch at the step's start,
  /// BA / (h EA + BA) (0 undamped): C - s = alpha lambda with s this times C_0 (direct_workspace.cpp).
  double dampingShiftShare() const
  {
    return axial_damping > 0.0 ? axial_damping / (time_step * axial_stiffness + axial_damping) : 0.0;
  }
  double bending_stiffness = 0;  ///< The largest EI [N m^2] (TetherParams::largestBendingStiffness()); xpbd, direct.
  /// EI bending acts: TetherParams::elasticBending() for the settings made from() them.
  bool elasticBending() const { return bending && bending_stiffness > 0.0; }
  double over_relaxation = 1.0;  ///< pbd: each correction times this (successive over-relaxation) [-].
  double tolerance = 1e-8;       ///< direct: stop when every residual is below this x its length [-].
  /// The winch's drum, for a solver that takes it into the step (takesDrum()): it decides the pay-out
  /// through the spool segment's law (spool_drum.hpp) and writes it into drum->payout. nullptr: none.
  SpoolDrum* drum = nullptr;

  /// The one place the settings are made from the parameters, for a (sub-)step of h [s].
  static SolverSettings from(const TetherParams& params, double h);
};

/**
 * The Lagrange multipliers of the last step, one per stretch constraint (segment j) and per bending
 * constraint (j, j+2), in kg m: the constraint force is lambda / h^2 [N] for the step h they were solved
 * for. Indexed like the cable's segments; a solver owns them and resets them every step.
 */
struct Multipliers
{
  std::vector<double> stretch;
  std::vector<double> bend;

  /// Sized for a cable of `particles` particles, all zero.
  void resize(std::size_t particles)
  {
    stretch.assign(particles > 0 ? particles - 1 : 0, 0.0);
    bend.assign(particles > 1 ? particles - 2 : 0, 0.0);
  }
  void clear()
  {
    std::fill(stretch.begin(), stretch.end(), 0.0);
    std::fill(bend.begin(), bend.end(), 0.0);
  }
};

/// A constraint residual or a segment strain of a whole segment length [-]: the solve has diverged (a chain folded
/// by a teleport or a violent pull; a real cable breaks long before). A sub-step that ends beyond it fails and the
/// cable is re-laid (Tether); `direct` first iterates past its budget to bring it back (DirectSolver::project).
inline constexpr double kDivergenceLimit = 1.0;

/**
 * Projects the distance and bending constraints of the deployed particles [first, size()), and the
 * contacts, once per step.
 *
 * Each method owns its multipliers (lambda, force = lambda / dt^2), which it resets and accumulates every
 * step, so tension is read after the step the same way whatever the method (tension.hpp). Methods: the
 * paper's pbd (red-black or sequential), xpbd (compliant), lumped_mass (explicit springs); see makeSolver.
 */
class ConstraintSolver
{
 public:
  virtual ~ConstraintSolver() = default;
  /// Projects the constraints, then the contacts on the free particles [first + 1, free_end); must not
  /// allocate.
  ///
  /// Friction of a contact that holds() is a force the step's solve balances, so the tension around the
  /// contact carries it (a capstan): after the solve and the contacts, each touching particle is held back
  /// against its slip by up to mu times its normal force (Contact::updateHold), the positions return to
  /// the step's prediction moved back by the holds, and the step is solved again; up to kFrictionPasses
  /// times, until no hold changes. The first solve starts from the last step's holds (Contact::warmStart),
  /// so a cable that keeps sticking or sliding as it did is solved once. A particle touching for the first
  /// time is first held by the full mu N (sliding); a particle the solve then moves backwards sticks, and
  /// its hold shrinks by that motion. A method that cannot solve again
  /// (lumped_mass) takes the friction as a correction after its solve.
  void solve(Cable& cable, const SolverSettings& settings, const Contacts& contacts, std::size_t free_end);
  static constexpr int kFrictionPasses = 4;
  /// Whether project() may be called again on the step's prediction (it projects positions from where
  /// they are); lumped_mass, which integrates forces, may not.
  virtual bool reprojects() const { return true; }
  /// True when the method meets a SpoolDrum's law within its step (direct); the others pay out before it.
  virtual bool takesDrum() const { return false; }
  /// Forgets what the method carries from step to step (a re-laid cable, a reset), so the next step is
  /// solved as a fresh run's first step.
  virtual void forget() {}
  /// Iterations the last solve() used when the method stops on a tolerance (direct), else -1.
  virtual int lastIterations() const { return -1; }
  /// Largest relative constraint residual the last solve() stopped at when the method measures it
  /// (direct), else NaN.
  virtual double lastResidual() const { return std::numeric_limits<double>::quiet_NaN(); }
  /// Largest segment strain seen by the last solve() when the method measures it (lumped_mass), else NaN.
  virtual double lastMaxStrain() const { return std::numeric_limits<double>::quiet_NaN(); }
  /// Whether a projection of the last solve() (any of its friction passes) went past its iterations to bring
  /// back a diverged solve (direct), counted in SolverEffort::rescued.
  bool lastRescued() const { return rescued_; }
  /// The largest segment strain such a projection ended with [-] (0 without one): kDivergenceLimit or more is
  /// a blow-up, which the tether answers as one (re-laid, counted, reported).
  double lastRescueStrain() const { return rescue_strain_; }
  const Multipliers& multipliers() const { return multipliers_; }
  /// For the tether: sized with the cable, cleared when the cable is re-laid or a particle is released.
  Multipliers& multipliers() { return multipliers_; }

 protected:
  /// The method's constraint projection; resets and accumulates `lambda`.
  virtual void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) = 0;
  /// For project(): it went past its iterations to bring back a diverged solve, ending at segment strain `strain`.
  void noteRescue(double strain)
  {
    rescued_ = true;
    rescue_strain_ = std::max(rescue_strain_, strain);
  }

 private:
  bool rescued_ = false;        ///< lastRescued(), reset by solve()
  double rescue_strain_ = 0.0;  ///< lastRescueStrain(), reset by solve()
  Multipliers multipliers_;
  std::vector<double> predicted_x_, predicted_y_, predicted_z_;  ///< The step's prediction, for the passes.
};

/// Creates the solver for `type` (pbd_solver.hpp and lumped_mass_solver.hpp hold the methods).
std::unique_ptr<ConstraintSolver> makeSolver(SolverType type);

}  // namespace rov_tether
