#pragma once

#include <vector>

#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{

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
  /// compliance rest / EA, so the multipliers converge to the physical force times dt^2 whatever the
  /// iteration count; bending stiffness EI acts at the joints (joint_bending.hpp) instead of the paper's
  /// (i, i+2) constraints.
  /// `direct_particles`: see kDirectParticles (tests set it to compare both paths).
  explicit PbdSolver(bool compliant = false, std::size_t direct_particles = kDirectParticles)
      : compliant_(compliant), direct_particles_(direct_particles)
  {
  }

 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;

 private:
  /// `stop`, `alpha_len`: xpbd's stretch lengths by cable index (dampedLengths; the rest lengths undamped).
  void solveDirect(Cable& cable, Multipliers& lambda, int iterations, bool bending, double stretch_compliance,
                   double inv_ei_h2, double relax, const double* stop, const double* alpha_len);
  /// xpbd with axial_damping: segment j's (a cable index) shifted length `stop` and the length `alpha_len`
  /// whose product with 1 / (EA dt^2) is its compliance (see the definition).
  static void dampedLengths(const Cable& cable, std::size_t j, const SolverSettings& settings, double* stop,
                            double* alpha_len);
  /// Where particle l of the deployed cable sits in the blocked arrays.
  std::size_t slot(std::size_t l) const { return (l & 3) * block_ + (l >> 2); }
  /// Copies the m deployed particles into the blocked arrays: their masses, rest lengths and weights where
  /// the cable marks them dirty (all when the layout shifted), their positions always; zeroes the multipliers.
  void copyIn(Cable& cable, std::size_t m);
  /// Copies the positions and the multipliers (the bending ones with `bending`) back to the cable.
  void copyOut(Cable& cable, Multipliers& lambda, std::size_t m, bool bending) const;

  bool compliant_;
  std::size_t direct_particles_;
  /// Particle and constraint data of the deployed cable in blocked order (4 blocks of `block_` each).
  std::vector<double> x_, y_, z_, inv_mass_;
  std::vector<double> rest_, weight_, lambda_;                 ///< Stretch constraint l joins l, l + 1.
  std::vector<double> bend_rest_, bend_weight_, bend_lambda_;  ///< Bending constraint l joins l, l + 2.
  std::vector<double> joint_x_, joint_y_, joint_z_;            ///< xpbd: joint l's three multipliers.
  std::vector<double> stop_, alpha_len_;              ///< xpbd with axial damping: stretch l's lengths (dampedLengths).
  std::vector<double> cable_stop_, cable_alpha_len_;  ///< The same by cable index, for the in-place path.
  std::size_t block_ = 0;
  std::size_t copied_first_ = static_cast<std::size_t>(-1);  ///< Layout of the copied constraint data.
  std::size_t copied_size_ = 0;
  std::size_t copied_block_ = 0;
};

/// The paper's Figure 2 in its literal order (segment 0, 1, 2, ... then bending 0, 1, ...). Kept as the
/// reference for the red-black solver's convergence and speed.
class SequentialPbdSolver : public ConstraintSolver
{
 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;
};

}  // namespace rov_tether
