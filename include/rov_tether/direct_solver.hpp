#pragma once

#include <vector>

#include "rov_tether/constraint_solver.hpp"

namespace rov_tether
{

/**
 * `direct`: Newton iterations on all of the chain's constraints at once, each solving
 *   (J M^-1 J^T + alpha / h^2) dlambda = C - alpha / h^2 lambda
 * exactly (Goldenthal et al. 2007, "fast projection"; Deul et al. 2018 do the same for rods). The
 * stretch constraints C_j = |x_j+1 - x_j| - L_j with the compliance L_j / EA make the matrix tridiagonal;
 * bending (bending_stiffness EI > 0 and `bending` on) adds, per pair of segments, the vector constraint
 *   C_b = (x_j+2 - x_j+1) / L_j+1 - (x_j+1 - x_j) / L_j,
 * the change of unit tangent (|C_b| = the angle for small angles), with compliance Lbar / EI, whose energy
 * EI theta^2 / (2 Lbar) is the discrete elastic rod's; the matrix is then banded (half-bandwidth 10).
 * The cost is O(N) per iteration whatever the length, the mass ratio or the stiffness.
 *
 * A cable carries no compression: a stretch constraint is unilateral (lambda >= 0). Each Newton
 * iteration solves with the active set (segments not shorter than their rest length, or carrying
 * tension, or that did at the end of the last step) and lets a segment whose multiplier would turn
 * negative go slack (lambda = 0); the next iteration's residuals take in what that changed. So a slack
 * segment carries nothing. Iterations stop when every residual is below `tolerance` x the segment length, or after
 * `iterations`; the count is reported.
 *
 * Multipliers are positive in tension, as for pbd: tension = lambda / h^2.
 */
class DirectSolver : public ConstraintSolver
{
 public:
  /// How the linear systems are solved: a plain LDL^T sweep written here, or LAPACK (dpttrf/dpttrs for
  /// the tridiagonal system, dpbtrf/dpbtrs for the banded one). Both give the same answer to rounding;
  /// `BM_TridiagonalSolve` and `BM_BandedSolve` measure which is faster (README, Benchmarks).
  enum class LinearSolve
  {
    kSweep,
    kLapack
  };
  explicit DirectSolver(LinearSolve linear = LinearSolve::kSweep) : linear_(linear) {}

  /// Newton iterations the last sub-step used (0: already within the tolerance).
  int lastIterations() const override { return iterations_; }
  /// Largest residual |C - alpha lambda| / L (or stretch of an inactive segment) when the last solve
  /// stopped [-].
  double lastResidual() const override { return residual_; }

  /// Half-bandwidth of the system with bending (rows: 4 per segment, stretch then the 3 bending rows).
  static constexpr int kBand = 10;

 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;

 private:
  /// Residuals of every constraint at the current positions; returns the largest relative one.
  double residuals(const Cable& cable, const Multipliers& lambda, bool bending, double tolerance);
  /// One Newton step into rhs_: assemble, solve, let segments that would push go slack.
  void newtonStep(Cable& cable, Multipliers& lambda, bool bending);
  /// Moves the particles by -M^-1 J^T rhs_ and adds rhs_ to the multipliers.
  void applyStep(Cable& cable, Multipliers& lambda, bool bending);
  /// Keeps / puts back the deployed positions and the multipliers, for the backtracking.
  void save(const Cable& cable, const Multipliers& lambda, bool bending);
  void restore(Cable& cable, Multipliers& lambda, bool bending);
  void solveTridiagonal(std::size_t rows);
  void solveBanded(std::size_t rows);
  void assembleBanded(const Cable& cable, const Multipliers& lambda, std::size_t segments);

  LinearSolve linear_;
  int iterations_ = 0;
  double residual_ = 0.0;
  // Per deployed segment k (global segment first + k), sized for the whole cable on the first step.
  std::vector<double> nx_, ny_, nz_;   ///< Unit vector of segment k.
  std::vector<double> stretch_c_;      ///< C_k = |d_k| - L_k [m].
  std::vector<double> stretch_alpha_;  ///< L_k / (EA h^2) [1/kg].
  std::vector<double> on_;             ///< 1: stretch constraint k is in the active set, 0: slack.
  std::vector<double> bend_c_;         ///< C_b of bending constraint k, 3 per k [-].
  std::vector<double> bend_lambda_;    ///< Its multipliers, 3 per k.
  std::vector<double> bend_alpha_;     ///< Lbar / (EI h^2) of bending constraint k.
  // The linear system: tridiagonal (diag_, off_) or banded lower (band_, kBand + 1 per column).
  std::vector<double> diag_, off_, rhs_, band_;
  std::vector<double> saved_x_, saved_y_, saved_z_, saved_lambda_, saved_bend_;
  double stretch_compliance_ = 0.0;  ///< 1 / (EA h^2) [1/(kg m)].
  double bend_compliance_ = 0.0;     ///< 1 / (EI h^2) [1/(kg m)].
};

}  // namespace rov_tether
