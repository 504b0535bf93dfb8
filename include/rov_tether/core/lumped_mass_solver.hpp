#pragma once

#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{

/**
 * A force-based lumped-mass chain: the second half of an explicit Verlet step. The tether has already
 * moved every particle by inertia, drag and weight (x holds the prediction, px the positions x_n); this adds
 * h^2 F(x_n) / m for the axial spring forces F = EA max(strain, 0) (a cable carries no compression). Stable
 * only for h < dL / sqrt(EA / mu) (TetherParams::criticalStep); the largest strain is reported so that a
 * blow-up is detected. No bending.
 */
class LumpedMassSolver : public ConstraintSolver
{
 public:
  double lastMaxStrain() const override { return max_strain_; }
  bool reprojects() const override { return false; }

 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;

 private:
  double max_strain_ = 0.0;
};

}  // namespace rov_tether
