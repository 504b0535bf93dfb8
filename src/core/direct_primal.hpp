#pragma once
// The direct solver's primal path: Newton on the positions and the multipliers together, with the step
// energy's full Hessian (geometric stiffness and EI bending included), a block-banded positive definite solve, an
// active-set model of the one-sided segments and an Armijo line search. See direct_solver.hpp.
#include <cstddef>
#include <vector>

#include "banded.hpp"
#include "direct_workspace.hpp"
#include "rov_tether/core/direct_solver.hpp"
#include "simd.hpp"

namespace rov_tether
{

class PrimalNewton
{
 public:
  PrimalNewton(DirectWorkspace& workspace, DirectSolver::LinearSolve linear) : ws_(workspace), linear_(linear) {}
  /// Sizes its buffers for a cable of n particles (once: pay-out never allocates).
  void reserve(std::size_t n);
  /// The first iterate: lambda = the last step's multipliers, the positions x~ plus the last step's
  /// correction x - x~ (the tension ratio makes W J^T lambda, each pull larger than a segment, too sensitive
  /// to where J is taken). `lambda` points at segment first's multiplier.
  void warmStart(Cable& cable, double* lambda);
  using Result = NewtonResult;
  /// Newton iterations from the multipliers in `lambda` (the dual's, or the warm start's) until the residual
  /// is below `tolerance` or `max_iterations` are spent, or a system is not definite; leaves the multipliers
  /// in `lambda` (a cable's clamped at 0).
  Result solve(Cable& cable, double* lambda, double tolerance, int max_iterations);
  /// The step's Hessian at the current positions (the workspace's geometry) for the multipliers `lambda`
  /// and the workspace's model (on()), as a Newton iteration assembles it but with a compressed segment's
  /// geometric stiffness bounded (assemble's default: always definite; not shifted), solved for `count` right-hand
  /// sides stored one after the other in `columns` (3 (m + 1) values each, overwritten with the solutions):
  /// one factorisation, then solves with it. False if the Hessian is not positive definite. For the end's
  /// linearisation (direct_end_stiffness.hpp); allocation-free once reserved.
  bool solveHessian(const Cable& cable, const double* lambda, double* columns, std::size_t count);

  /// The deployed particles' arrays the assembly and the residual read, by particle l: inverse mass (0 pinned),
  /// mass, extra mass along the cable, position, prediction x~, tangent (null without added mass).
  struct Particles
  {
    const double *w, *mass, *less, *x, *y, *z, *xt, *yt, *zt, *tx, *ty, *tz;
  };

 private:
  Particles particles(const Cable& cable) const;
  /// The step's energy Phi(x) at the current positions.
  double energy(const Cable& cable) const;
  /// The force (multiplier) segment k carries at stretch c: its law (one-sided for a cable; the drum's for
  /// the spool segment when there is one).
  double segmentForce(std::size_t k, double c) const;
  /// 1 when segment k, off the taut branch (taut 0) at stretch c, is on its law's middle piece, else 0.
  double onMiddle(std::size_t k, double taut, double c) const
  {
    return taut == 0.0 && ws_.dashpot[k] > 0.0 && c > ws_.zero[k] ? 1.0 : 0.0;
  }
  /// Segment k is in the model on its law's middle piece (this step has one for it).
  bool inMiddle(std::size_t k) const { return ws_.dashpot[k] > 0.0 && middle_[k] > 0.0; }
  /// What stays the same through a step's Newton iterations (prepareBending), and the curvature.
  void prepare(const Cable& cable);
  /// The bending joints' constant terms of each block row into bend_diag_, bend_pull_, bend_first_ and the
  /// second blocks below (hessian_second_).
  void prepareBending(const Cable& cable);
  /// The bending joints' curvatures at the current positions into curve_x_, curve_y_, curve_z_ (with
  /// bending): after every change of the positions, before energy(), residual() or assemble() read them.
  void curvature(const Cable& cable);
  /// The Hessian's blocks and the gradient at the current positions, for the model's segments: the mass, the
  /// segments' axial and geometric stiffness, the joints' bending. Each segment's terms first, into segment_,
  /// then the rows from them, in loops that vectorise (direct_primal_assembly.cpp). `whole_compression`: every
  /// compressed segment's geometric stiffness whole (the exact Hessian, which a buckling rod makes indefinite),
  /// else each at most kCompressedShare of its ends' masses (always definite).
  void assemble(const Cable& cable, bool whole_compression = false);
  /// Adds shift x each particle's mass to the diagonal of assemble()'s Hessian (not to the gradient).
  void shiftHessian(double shift);
  /// Solves for the model's Newton step into step_, the model's active set (the workspace's on()) with it,
  /// counting the linear solves into `rounds`; false if a system is not definite.
  bool solveModel(const Cable& cable, int* rounds);
  /// With the drum, where pulledSolve does not apply (LAPACK, or a spool particle that is not pinned): step_
  /// (the solve without the spool segment's force) becomes the step that meets the drum's law, through a second
  /// solve for a unit pull, and lambda_step_[0] its force's change; false if that solve is not definite.
  /// `second`: the Hessian has a second band (bending).
  bool drumStep(bool second);
  /// The model's solve with the drum's law in it (banded::solveBlockBandedPulled: the spool's particle
  /// pinned, the sweep), into step_ and lambda_step_[0]; false if not definite. `second`: the second band or
  /// nullptr.
  bool pulledSolve(const double* second);
  /// Segment k's stretch C_k + n_k . (dx_k+1 - dx_k) after step_, and the change n_k . (dx_k+1 - dx_k).
  double linearStretch(std::size_t k) const;
  double alongSegment(std::size_t k) const;
  /// Each multiplier's Newton step into lambda_step_.
  void multiplierStep(const Cable& cable);
  /// The energy's slope along step_.
  double slope() const;
  /// One Newton step with line search; returns the largest relative move |dx| / L taken (infinite when a
  /// system was not definite).
  double step(Cable& cable, int* rounds);
  /// The largest residual of the step's equations at the current positions and multipliers, as a
  /// displacement relative to the segment length: the force balance M (x - x~) + J^T lambda (+ bending)
  /// of each free particle times its inverse mass, and C - alpha lambda of each segment (max(C, 0) of one
  /// out of the model; lambda against the law for the drum's).
  double residual(const Cable& cable);
  /// Whether a rod's residual is above `tolerance` by one of its segments' own (every 8th looked at): true says the
  /// residual() is too; false says nothing.
  bool segmentAbove(double tolerance) const;

  /// Where assemble() puts the Hessian's blocks: one array an entry, n long (n the particles reserved).
  banded::BlockLayout layout() const { return {1, lambda_.size()}; }
  /// Term i's array of a vector of per-row terms stored one array a term, n long (bend_diag_ and the like).
  double* term(std::vector<double>& terms, std::size_t i) { return terms.data() + i * lambda_.size(); }
  /// segment_'s i-th array (n + 1 long).
  double* segmentArray(std::size_t i) { return segment_.data() + i * (lambda_.size() + 1); }

  DirectWorkspace& ws_;
  DirectSolver::LinearSolve linear_;
  /// The Hessian's 3x3 blocks (diagonal and first below), 9 a particle (layout(); of the diagonal blocks only the
  /// lower triangle is assembled, the rest stays 0: the block solves read no other), and the second below (c I: c,
  /// one a particle); the Newton step and the gradient, 3 a particle; the block solve's workspace, and LAPACK's
  /// band.
  std::vector<double> hessian_diag_, hessian_first_, hessian_second_, step_, grad_, grad_step_, work_, band_;
  /// Each particle's mass (0 pinned), its extra mass along the cable (m_along - m_across), each
  /// segment's 1 / alpha: constant through a step (prepare()).
  std::vector<double> mass_, mass_less_, stiffness_;
  /// Each bending joint's curvature at the current positions, by axis (curvature()): joint j at j + 2, the
  /// two entries on either side 0.
  std::vector<double> curve_x_, curve_y_, curve_z_;
  /// A block row's bending terms (prepareBending), constant through a step: the diagonal's sum over its joints
  /// l - 2, l - 1, l of g_r^2 / gamma (at l), each joint's g_r / gamma (i = 0, 1, 2: the curvature's pull on the
  /// particle, in the order the gradient adds them), and two for the first block below; term i of row l at
  /// i n + l (n the particles reserved: each term's own array, for the vectorised rows).
  std::vector<double> bend_diag_, bend_pull_, bend_first_;
  /// Each segment's terms of an assembly (on, force, scale, geometric stiffness, n_x, n_y, n_z: seven arrays of
  /// n + 1, segment k at k + 1 of each, 0 before the first and after the last).
  std::vector<double> segment_;
  /// The multipliers as unknowns of their own (Newton on positions and multipliers together, the
  /// multipliers eliminated from each linear solve), and their change over a Newton step.
  std::vector<double> lambda_, lambda_step_;
  /// The model's segments on their law's middle piece, 1 or 0 (its value counts only where the segment has a
  /// dashpot's middle piece this step).
  std::vector<double> middle_;
  /// energy()'s terms (energyTerms): four arrays of n + 1.
  mutable std::vector<double> energy_terms_;
  /// The energy at the current positions, when the last line search computed it there (energy_known_).
  double known_energy_ = 0.0;
  bool energy_known_ = false;
  /// The last Newton iteration's model had not settled in kMaxModelRounds: the next starts from it.
  bool model_unsettled_ = false;
  /// This solve's Hessians keep every compressed segment's geometric stiffness (the exact Hessian; assemble's
  /// whole_compression), shifted while not definite: false once even the largest shift was not (solveModel).
  bool whole_compression_ = true;
};

/// What energyTerms reads besides the particles: each segment's stretch and law (DirectWorkspace's), and each
/// bending joint's curvature (joint j at j + 2) and stiffness.
struct EnergyLaw
{
  const double *c, *alpha, *kink, *zero, *dashpot, *curve[3], *inv_gamma;
};

/// The step energy's terms, each as PrimalNewton's energy adds them, into `terms` (four arrays of `stride`):
/// each of the m + 1 particles' kinetic (M (x - x~)).(x - x~) across, then along the cable (0 for a pinned one;
/// the second only with added mass, `along`, and not written without), each of the m segments' twice its potential (the
/// integral of its law from where the law is 0; the caller adds a drum's apart), each joint's |kappa|^2 / gamma.
/// Branch-free, so that it vectorises; each term the same operations in the same order whatever the vector
/// width, so that the caller's sum in order is the same to the bit on every machine.
void energyTerms(const PrimalNewton::Particles& p, const EnergyLaw& law, std::size_t m, bool along, bool unilateral,
                 bool bending, double* terms, std::size_t stride);

/// What bendingRows reads and writes: the particles' inverse masses, the segments' inverse rest lengths and the
/// joints' stiffness; each row's three joints' pulls g / gamma (term i of row l at i n + l) and the sum of their
/// diagonal terms, its two first-below terms and its second-below coefficient.
struct BendingRows
{
  const double *w, *inv_rest, *inv_gamma;
  double *pull[3], *diag, *first[2], *second;
};

/// PrimalNewton::prepareBending's rows `from` to `to` - 1, each of which has all three of its joints (l - 2,
/// l - 1, l), the particle after it and the one after that: 2 <= from, to <= m - 1. The same operations as the
/// general rows, their conditions reduced to the particles being free; branch-free, so that it vectorises.
void bendingRows(const BendingRows& rows, std::size_t from, std::size_t to);

/// Particle l's three bending joints' pulls (joints l - 2, l - 1, l, in that order: PrimalNewton's bend_pull_)
/// times their curvatures (offset by 2: joint l - 2 + i at entry l + i) added to the force (f0, f1, f2), as the
/// assembly's gradient and the residual's force balance both add them.
ROV_TETHER_INLINE void addJointPulls(const double* __restrict p0, const double* __restrict p1,
                                     const double* __restrict p2, const double* __restrict cx,
                                     const double* __restrict cy, const double* __restrict cz, std::size_t l,
                                     double& f0, double& f1, double& f2)
{
  f0 += p0[l] * cx[l], f1 += p0[l] * cy[l], f2 += p0[l] * cz[l];
  f0 += p1[l] * cx[l + 1], f1 += p1[l] * cy[l + 1], f2 += p1[l] * cz[l + 1];
  f0 += p2[l] * cx[l + 2], f1 += p2[l] * cy[l + 2], f2 += p2[l] * cz[l + 2];
}

}  // namespace rov_tether
