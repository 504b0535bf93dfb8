#pragma once

#include <Eigen/Core>
#include <memory>

#include "rov_tether/core/constraint_solver.hpp"

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
 *   compression, a rod's whole, plus a multiple of the masses while that is not positive definite; once even
 *   64 masses are not enough, for the rest of that solve only while it takes at most an eighth of either
 *   end's mass, which is positive definite). The dual path leaves it out: a tensioned chain's transverse step
 *   is then explicit, and unstable beyond that ratio (Tournier et al. 2015, "Stable constrained dynamics").
 *   The multipliers are unknowns of their own (the saddle-point system of that paper, with them eliminated
 *   from each solve): the geometric stiffness uses their Newton estimate, not C(x) / alpha, which a nearly
 *   inextensible segment (alpha -> 0) makes useless. Block-banded systems (factored only when positive
 *   definite), an active-set model for the one-sided segments and an Armijo line search on Phi (convex for a
 *   cable).
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
  /// which is faster (docs/benchmarks.md).
  enum class LinearSolve
  {
    kSweep,
    kLapack
  };
  explicit DirectSolver(LinearSolve linear = LinearSolve::kSweep);
  ~DirectSolver() override;
  DirectSolver(const DirectSolver&) = delete;
  DirectSolver& operator=(const DirectSolver&) = delete;

  /// Newton iterations the last sub-step used, both paths (0: already within the tolerance).
  int lastIterations() const override { return dual_iterations_ + primal_iterations_; }
  /// Of those, the iterations on the primal path (full Hessian).
  int lastPrimalIterations() const { return primal_iterations_; }
  /// Linear solves of the active-set rounds (dual) and model rounds (primal) in the last sub-step.
  int lastActiveSetRounds() const { return active_set_rounds_; }
  /// Largest relative residual when the last solve stopped [-].
  double lastResidual() const override { return residual_; }
  /// A sub-step whose Newton has diverged after `iterations` (a residual of kDivergenceLimit or more) goes on for
  /// up to kRescueBudget times `iterations` more, at most kMaxRescueIterations (project(); lastRescued(), and
  /// lastIterations() counts them).
  static constexpr int kRescueBudget = 2;
  static constexpr int kMaxRescueIterations = 100;
  bool takesDrum() const override { return true; }
  void forget() override;

  /// The last step's linearisation at a pinned last particle (a kinematic vehicle end): K = dF/dx [N/m] of
  /// the pull F = -lambda n / h^2 of the last segment on it, with respect to where it was at the step's end,
  /// the other particles answering through the step's Newton system (end_linearisation.hpp, docs/model.md
  /// "A kinematic end's linearisation for external simulators"). `cable` and the multipliers are the step's
  /// result; `settings` the step's (time_step the sub-step h). Zero and *taut false when the last segment
  /// carries no tension; false when the system is not positive definite. `horizon` [s] > h linearises a step
  /// of that length instead (the particles' inertia M / horizon^2). The step's warm start is not touched (a
  /// workspace of its own); allocation-free after the first call.
  bool endStiffness(const Cable& cable, const SolverSettings& settings, double horizon, Eigen::Matrix3d* stiffness,
                    bool* taut);

 protected:
  void project(Cable& cable, Multipliers& lambda, const SolverSettings& settings) override;

 private:
  /// The workspace the two paths share and the two Newton methods over it (src/core: direct_workspace.hpp,
  /// direct_dual.hpp, direct_primal.hpp). Made once, with the solver; sized on the first step.
  struct Methods;

  int dual_iterations_ = 0;
  int primal_iterations_ = 0;
  int active_set_rounds_ = 0;
  double residual_ = 0.0;
  std::unique_ptr<Methods> methods_;
};

}  // namespace rov_tether
