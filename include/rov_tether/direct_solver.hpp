#pragma once

#include <vector>

#include "rov_tether/constraint_solver.hpp"

namespace rov_tether
{

/**
 * `direct`: the implicit step of the whole chain solved by Newton's method with exact linear solves, O(N)
 * per iteration whatever the length, the stiffness or the mass ratio.
 *
 * The step's unknowns are the positions x and the multipliers lambda [kg m] (force = lambda / h^2) for the
 * predicted positions x~ (inertia, drag, weight, noise), with compliant constraints (XPBD's):
 *   M (x - x~) + J(x)^T lambda = 0,   C(x) - alpha lambda = 0,   C = |d| - L,  alpha = L / (EA h^2).
 * A cable carries no compression: without bending stiffness each segment is one-sided (lambda >= 0, and a
 * segment shorter than its rest length carries nothing). With bending stiffness the chain is a rod: its
 * segments carry compression and its joints resist bending with C_b = d_j+1 / L_j+1 - d_j / L_j (the change
 * of tangent, |C_b| the angle for small angles) and compliance gamma = Lbar / (EI h^2): the discrete elastic
 * rod's energy EI theta^2 / (2 Lbar), linear in the angle as the paper's (i, i+2) constraint is not.
 *
 * Two Newton paths:
 * - **dual** (no bending stiffness, low tension): Newton on the multipliers, each iteration solving
 *   (J W J^T + alpha) dlambda = C - alpha lambda exactly, a tridiagonal system (Goldenthal et al. 2007's fast
 *   projection with XPBD's compliance), the particles moving by W J^T dlambda. The one-sided segments form
 *   a primal-dual active set (Hintermueller, Ito, Kunisch 2003) solved on each linearisation.
 * - **primal** (bending stiffness, or a tension ratio h^2 T (w_a + w_b) / |d| above 1/4): Newton on the
 *   positions and the multipliers together, minimising the step's energy
 *     Phi(x) = 1/2 |x - x~|_M^2 + sum max(C_k, 0)^2 / (2 alpha_k) + sum |C_b|^2 / (2 gamma_b)
 *   (max only for a cable) with the full Hessian, geometric stiffness lambda / |d| (I - n n^T) included (in
 *   compression, a rod's, only while it takes at most an eighth of either end's mass: positive definite). The
 *   dual path leaves it out: a tensioned chain's transverse step is then explicit, and unstable beyond that
 *   ratio (Tournier et al. 2015, "Stable constrained dynamics"). The multipliers are unknowns of their own
 *   (the saddle-point system of that paper, with them eliminated from each solve): the geometric stiffness
 *   uses their Newton estimate, not C(x) / alpha, which a nearly inextensible segment (alpha -> 0) makes
 *   useless. Block-banded SPD systems, an active-set model for the one-sided segments and an Armijo line
 *   search on Phi (convex for a cable).
 * The dual path is taken first; the primal takes over when the last step's tension ratio exceeds 1/4, or
 * when a dual iteration fails to lower the residual.
 *
 * Iterations stop when every residual is below `tolerance` x the segment length: |C - alpha lambda| of every
 * pulling segment and lambda (w_a + w_b) of every slack one (dual), and the force balance of every particle
 * as a displacement (primal; no extra solve is spent to confirm convergence).
 */
class DirectSolver : public ConstraintSolver
{
 public:
  /// How the linear systems are solved: the plain sweeps written in banded.cpp, or LAPACK (dpttrf/dpttrs,
  /// dpbtrf/dpbtrs). Both give the same answer to rounding; BM_TridiagonalSolve and BM_BandedSolve measure
  /// which is faster (README, Benchmarks).
  enum class LinearSolve
  {
    kSweep,
    kLapack
  };
  explicit DirectSolver(LinearSolve linear = LinearSolve::kSweep) : linear_(linear) {}

  /// Newton iterations the last sub-step used, both paths (0: already within the tolerance).
  int lastIterations() const override { return dual_iterations_ + primal_iterations_; }
  /// Of those, the iterations on the primal path (full Hessian).
  int lastPrimalIterations() const { return primal_iterations_; }
  /// Linear solves of the dual path's active-set rounds in the last sub-step.
  int lastActiveSetRounds() const { return active_set_rounds_; }
  /// Largest relative residual when the last solve stopped [-].
  double lastResidual() const override { return residual_; }
  bool takesDrum() const override { return true; }
  void forget() override;

 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;

 private:
  /// Sizes every buffer for a cable of n particles (once: pay-out never allocates).
  void reserve(std::size_t n);
  /// Segment geometry at the current positions: n_k, |d_k|, C_k.
  void geometry(const Cable& cable);
  /// Starts from the last step's multipliers and, on the primal path, its correction of the positions.
  void warmStart(Cable& cable, double* lambda, bool primal);
  // Dual path (direct_solver.cpp).
  double dualResidual(const Cable& cable, const double* lambda);
  /// Solves the tridiagonal system for the active set on_ into step(); false if it is not definite.
  bool solveRows();
  /// The same with row 0 (the spool segment) on the drum's law, met exactly (two solves).
  bool solveWithDrum(const double* lambda);
  void dualStep(Cable& cable, double* lambda);
  // Primal path (direct_solver_primal.cpp).
  double energy(const Cable& cable) const;
  /// The force (multiplier) segment k carries at stretch c: its law (one-sided for a cable; the drum's for
  /// the spool segment when there is one).
  double segmentForce(std::size_t k, double c) const;
  /// One Newton step with line search; returns the largest relative move |dx| / L taken.
  double primalStep(Cable& cable);
  /// The largest residual of the step's equations at the current positions and multipliers, as a
  /// displacement relative to the segment length: the force balance M (x - x~) + J^T lambda (+ bending)
  /// of each free particle times its inverse mass, and C - alpha lambda of each segment (max(C, 0) of one
  /// out of the model; lambda against the law for the drum's).
  double primalResidual(const Cable& cable) const;
  void assemblePrimal(const Cable& cable);
  void save(const Cable& cable);
  void restore(Cable& cable) const;

  LinearSolve linear_;
  int dual_iterations_ = 0;
  int primal_iterations_ = 0;
  int active_set_rounds_ = 0;
  SpoolDrum* drum_ = nullptr;  ///< The winch's drum in this step, or none.
  double residual_ = 0.0;
  double tension_ratio_ = 0.0;  ///< Largest h^2 T (w_a + w_b) / |d| of the last step [-].

  // The step being solved (deployed particles l = 0..m, segments k = 0..m-1, joints j = 0..m-2).
  std::size_t first_ = 0;
  std::size_t m_ = 0;
  bool bending_ = false;
  bool unilateral_ = true;
  double nominal_ = 0.1;                          ///< Nominal segment length, the scale of the position tolerance [m].
  std::vector<double> xt_, yt_, zt_;              ///< Predicted positions x~ [m].
  std::vector<double> sx_, sy_, sz_;              ///< Saved positions (rejected steps).
  std::vector<double> nx_, ny_, nz_, len_;        ///< Unit vector and length of segment k.
  std::vector<double> c_;                         ///< C_k = |d_k| - L_k [m].
  std::vector<double> alpha_;                     ///< alpha_k = L_k / (EA h^2) [1/kg].
  std::vector<double> inv_rest_;                  ///< 1 / L_k [1/m].
  std::vector<double> extra_mobility_;            ///< w_along - w_across of particle l (added mass) [1/kg].
  std::vector<double> response_, zeros_;          ///< Dual with the drum: the solve with dlambda_0 = 0; zeros.
  std::vector<double> diag_, off_;                ///< Dual: the tridiagonal system.
  std::vector<double> diag_active_, rhs_active_;  ///< Dual: every row as if active.
  // Dual, padded with a zero before row 0 and after row m - 1 (the accessors point at row 0): the active set
  // (1 or 0), each row's coupling to the next, the multipliers, and the step dlambda (the system's
  // right-hand side, then its solution).
  std::vector<double> on_, coupling_, padded_lambda_, dual_step_;
  double* on() { return on_.data() + 1; }
  double* coupling() { return coupling_.data() + 1; }
  double* padded_lambda() { return padded_lambda_.data() + 1; }
  double* step() { return dual_step_.data() + 1; }
  std::vector<double> gamma_;  ///< Primal: compliance of bending joint j [1/(kg m^2)].
  /// Primal: the Hessian's 3x3 blocks (diagonal, first and second below), 9 a particle; the Newton step and
  /// the gradient, 3 a particle; the block solve's workspace, and LAPACK's band.
  std::vector<double> hessian_diag_, hessian_first_, hessian_second_, step_, grad_, grad_step_, work_, band_;
  std::vector<double> saved_lambda_;
  /// Primal: the multipliers as unknowns of their own (Newton on positions and multipliers together, the
  /// multipliers eliminated from each linear solve); their change over a Newton step; the last step's
  /// multipliers, by particle index, the first estimate.
  std::vector<double> primal_lambda_, lambda_step_, warm_lambda_;
  /// The last step's correction x - x~ of each particle, by particle index [m]: the primal path's first guess.
  std::vector<double> correction_x_, correction_y_, correction_z_;
  std::vector<unsigned char> taut_;
};

}  // namespace rov_tether
