// DirectSolver: the front over the two Newton methods (direct_dual.hpp, direct_primal.hpp) and the
// workspace they share (direct_workspace.hpp). It sets the step up, picks the path and ends the step.
#include "rov_tether/core/direct_solver.hpp"

#include <algorithm>
#include <cmath>

#include "direct_dual.hpp"
#include "direct_end_stiffness.hpp"
#include "direct_primal.hpp"
#include "direct_workspace.hpp"

namespace rov_tether
{
namespace
{

/// The dual path hands over to the primal when the last step's tension ratio h^2 T (w_a + w_b) / |d| is
/// above this: the dual iteration's error in a chain's zig-zag mode is multiplied by about twice the
/// ratio each iteration (it leaves out the geometric stiffness), so above 1/4 it would converge slowly,
/// above 1/2 not at all.
constexpr double kDualTensionRatio = 0.25;
/// Dual iterations before the primal takes over (the dual converges in 1-3 where it should).
constexpr int kMaxDualIterations = 10;

/// The largest strain |x_k+1 - x_k| / L_k - 1 of the deployed segments [-].
double largestStrain(const Cable& cable)
{
  double largest = 0.0;
  for (std::size_t k = cable.first; k + 1 < cable.size(); ++k)
  {
    largest = std::max(largest, cable.strain(k));
  }
  return largest;
}

}  // namespace

struct DirectSolver::Methods
{
  explicit Methods(LinearSolve linear) : dual(workspace, linear), primal(workspace, linear), end(linear) {}
  Methods(const Methods&) = delete;
  Methods& operator=(const Methods&) = delete;

  DirectWorkspace workspace;
  DualNewton dual;
  PrimalNewton primal;
  EndStiffness end;  ///< The end's linearisation, on demand (its own workspace: empty until first used).
};

DirectSolver::DirectSolver(LinearSolve linear) : methods_(std::make_unique<Methods>(linear)) {}

DirectSolver::~DirectSolver() = default;

void DirectSolver::project(Cable& cable, Multipliers& lambda, const SolverSettings& settings)
{
  DirectWorkspace& workspace = methods_->workspace;
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  dual_iterations_ = primal_iterations_ = active_set_rounds_ = 0;
  residual_ = 0.0;
  if (n < f + 2)
  {
    workspace.tension_ratio = 0.0;
    return;
  }
  workspace.reserve(n);
  methods_->dual.reserve(n);
  methods_->primal.reserve(n);
  workspace.begin(cable, lambda, settings);
  double* lam = lambda.stretch.data() + f;
  const double tolerance = settings.tolerance;
  // The dual path first, unless the chain is a rod or was pulled too hard in the last step; the primal
  // takes over from where the dual stopped.
  // The dual has no dashpot's middle piece (DirectWorkspace::kink): a damped cable with a slack segment goes
  // to the primal.
  bool primal = workspace.bending || workspace.dashpots || workspace.tension_ratio > kDualTensionRatio;
  if (primal)
  {
    methods_->primal.warmStart(cable, lam);
  }
  else
  {
    methods_->dual.warmStart(cable, lam);
    const DualNewton::Result dual =
        methods_->dual.solve(cable, lam, tolerance, std::min(settings.iterations, kMaxDualIterations));
    dual_iterations_ = dual.iterations;
    active_set_rounds_ += dual.rounds;
    residual_ = dual.residual;
    primal = residual_ > tolerance && dual_iterations_ < settings.iterations;
  }
  if (primal)
  {
    const PrimalNewton::Result result =
        methods_->primal.solve(cable, lam, tolerance, settings.iterations - dual_iterations_);
    primal_iterations_ = result.iterations;
    active_set_rounds_ += result.rounds;
    residual_ = result.residual;
  }
  // Diverged within the budget: a constraint still violated by a whole segment length, which the tether would
  // answer by re-laying the cable at rest. Newton with its line search brings such a step back when given more
  // iterations (a sharp turn of a fine cable with bending, docs/limitations.md), so it goes on, on the primal
  // path from the positions and multipliers it reached, for up to kRescueBudget times the budget more (at most
  // kMaxRescueIterations); counted, and re-laid after all if that is not enough or if it ends with a segment
  // stretched by kDivergenceLimit or more (a blow-up the residual alone would not show; ConstraintSolver::
  // lastRescueStrain). Not for an infinite residual (a system that is not definite: more iterations would
  // meet it again) nor NaN (a non-finite cable).
  if (std::isfinite(residual_) && residual_ >= kDivergenceLimit)
  {
    const int budget = std::min(kRescueBudget * std::max(settings.iterations, 1), kMaxRescueIterations);
    const PrimalNewton::Result more = methods_->primal.solve(cable, lam, tolerance, budget);
    primal_iterations_ += more.iterations;
    active_set_rounds_ += more.rounds;
    residual_ = more.residual;
    noteRescue(largestStrain(cable));
  }
  workspace.end(cable, lam);
}

void DirectSolver::forget() { methods_->workspace.forget(); }

bool DirectSolver::endStiffness(const Cable& cable, const SolverSettings& settings, double horizon,
                                Eigen::Matrix3d* stiffness, bool* taut)
{
  return methods_->end.compute(cable, multipliers(), settings, horizon, stiffness, taut);
}

}  // namespace rov_tether
