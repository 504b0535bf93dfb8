// The direct solver's primal path (direct_primal.hpp): Newton on the positions with the step energy's full
// Hessian (geometric stiffness and EI bending included; shifted while not positive definite), a banded
// positive definite solve and a backtracking line search.
// See direct_solver.hpp.
#include "direct_primal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "banded.hpp"
#include "simd.hpp"

namespace rov_tether
{
namespace
{

/// Below this largest relative move a Newton step is taken whole: the quadratic model is good there.
constexpr double kGlobalMove = 1e-3;
/// Halvings of a step that does not lower the energy enough (Armijo, slope fraction kArmijo).
constexpr int kMaxHalvings = 12;
constexpr double kArmijo = 1e-4;
/// Rounds of the model's active set in one Newton step.
constexpr int kMaxModelRounds = 30;
/// The first and the largest shift of a Hessian that is not definite, in particle masses (solveModel).
constexpr double kFirstShift = 0.125;
constexpr double kMaxShift = 64.0;

/// The largest magnitude of `count` numbers (0 for none).
ROV_TETHER_TARGET_CLONES double largestComponent(const double* __restrict v, std::size_t count)
{
  double largest = 0.0;
#pragma omp simd reduction(max : largest)
  for (std::size_t i = 0; i < count; ++i)
  {
    largest = std::max(largest, std::abs(v[i]));
  }
  return largest;
}

/// The sum of a[i] b[i] (b nullptr: of a[i]) over `count` entries, in four running sums (entry i into sum i mod 4)
/// added pairwise at the end: a fixed order, whatever the vector width, and a quarter of the chain of dependent
/// additions a single running sum makes.
double sumOf(const double* __restrict a, const double* __restrict b, std::size_t count)
{
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  std::size_t i = 0;
  for (; i + 4 <= count; i += 4)
  {
    for (std::size_t j = 0; j < 4; ++j)
    {
      sum[j] += b != nullptr ? a[i + j] * b[i + j] : a[i + j];
    }
  }
  for (std::size_t j = 0; i + j < count; ++j)  // the last count % 4 entries
  {
    sum[j] += b != nullptr ? a[i + j] * b[i + j] : a[i + j];
  }
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

}  // namespace

void PrimalNewton::reserve(std::size_t n)
{
  if (lambda_.size() >= n)
  {
    return;
  }
  for (auto* v : {&lambda_, &lambda_step_, &middle_, &hessian_second_, &mass_, &mass_less_, &stiffness_})
  {
    v->assign(n, 0.0);
  }
  for (auto* v : {&curve_x_, &curve_y_, &curve_z_})
  {
    v->assign(n + 4, 0.0);  // offset by 2, zeros on either side
  }
  bend_diag_.assign(n, 0.0);
  bend_pull_.assign(3 * n, 0.0);
  bend_first_.assign(2 * n, 0.0);
  segment_.assign(7 * (n + 1), 0.0);
  for (auto* v : {&hessian_diag_, &hessian_first_})
  {
    v->assign(9 * n, 0.0);
  }
  step_.assign(3 * n, 0.0);
  grad_.assign(3 * n, 0.0);
  grad_step_.assign(3 * n, 0.0);
  energy_terms_.assign(4 * (n + 1), 0.0);
  work_.assign(36 * n, 0.0);
  band_.assign(9 * 3 * n, 0.0);  // LAPACK's band, up to half-bandwidth 8
}

void PrimalNewton::warmStart(Cable& cable, double* lambda)
{
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  const double* w = cable.inv_mass.data() + f;
  std::copy(ws_.warm_lambda.begin() + static_cast<std::ptrdiff_t>(f),
            ws_.warm_lambda.begin() + static_cast<std::ptrdiff_t>(f + m), lambda);
  for (std::size_t l = 0; l <= m; ++l)
  {
    const double free = w[l] > 0.0 ? 1.0 : 0.0;
    cable.x[f + l] += free * ws_.correction_x[f + l];
    cable.y[f + l] += free * ws_.correction_y[f + l];
    cable.z[f + l] += free * ws_.correction_z[f + l];
  }
  ws_.geometry(cable);
}

PrimalNewton::Result PrimalNewton::solve(Cable& cable, double* lambda, double tolerance, int max_iterations)
{
  const std::size_t m = ws_.m;
  std::copy(lambda, lambda + m, lambda_.begin());
  prepare(cable);
  energy_known_ = false;
  Result result;
  result.residual = std::numeric_limits<double>::infinity();
  model_unsettled_ = false;
  whole_compression_ = true;
  bool above = false;  // the last iteration's residual is known only to be above the tolerance
  while (result.residual > tolerance && result.iterations < max_iterations)
  {
    if (!std::isfinite(step(cable, &result.rounds)))
    {
      // The system was not definite: leave the step as it is (reported through the residual; a rod's failed
      // step changed nothing the residual reads).
      result.residual = above ? residual(cable) : result.residual;
      break;
    }
    ++result.iterations;
    // Another iteration follows whenever the residual is above the tolerance, which a rod's segment's own
    // residual above it already says (the residual is the largest of all); the last iteration's is computed whole.
    above = !ws_.unilateral && result.iterations < max_iterations && segmentAbove(tolerance);
    result.residual = above ? std::numeric_limits<double>::infinity() : residual(cable);
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    lambda[k] = ws_.unilateral ? std::max(lambda_[k], 0.0) : lambda_[k];
  }
  return result;
}

bool PrimalNewton::solveHessian(const Cable& cable, const double* lambda, double* columns, std::size_t count)
{
  const std::size_t m = ws_.m;
  const std::size_t rows = 3 * (m + 1);
  std::copy(lambda, lambda + m, lambda_.begin());
  prepare(cable);
  assemble(cable);
  const double* second = ws_.bending ? hessian_second_.data() : nullptr;
  for (std::size_t column = 0; column < count; ++column)
  {
    double* b = columns + column * rows;
    bool ok = true;
    if (linear_ == DirectSolver::LinearSolve::kLapack)
    {
      ok = column == 0 ? banded::solveBlockBandedLapack(hessian_diag_.data(), hessian_first_.data(), second, b, m + 1,
                                                        band_.data(), layout())
                       : banded::solveBlockBandedLapackAgain(second != nullptr, b, m + 1, band_.data());
    }
    else if (column == 0)
    {
      ok = banded::solveBlockBanded(hessian_diag_.data(), hessian_first_.data(), second, b, m + 1, work_.data(),
                                    layout());
    }
    else
    {
      banded::solveBlockBandedAgain(second != nullptr, b, m + 1, work_.data());
    }
    if (!ok)
    {
      return false;
    }
  }
  return true;
}

namespace
{

/// energyTerms, compiled for each instruction set (the header's declaration cannot carry the clones: a caller
/// would make a resolver of its own).
ROV_TETHER_TARGET_CLONES void energyTermsCloned(const PrimalNewton::Particles& p, const EnergyLaw& law, std::size_t m,
                                                bool along, bool unilateral, bool bending, double* __restrict terms,
                                                std::size_t stride)
{
  const double* __restrict w = p.w, * __restrict mass = p.mass, * __restrict less = p.less;
  const double* __restrict x = p.x, * __restrict y = p.y, * __restrict z = p.z;
  const double* __restrict xt = p.xt, * __restrict yt = p.yt, * __restrict zt = p.zt;
  const double* __restrict tx = p.tx, * __restrict ty = p.ty, * __restrict tz = p.tz;
  double* __restrict across = terms, * __restrict lengthwise = terms + stride;
  double* __restrict elastic = terms + 2 * stride, * __restrict bent = terms + 3 * stride;
  if (along)
  {
#pragma omp simd
    for (std::size_t l = 0; l <= m; ++l)
    {
      const double dx = x[l] - xt[l], dy = y[l] - yt[l], dz = z[l] - zt[l];
      const bool free = w[l] > 0.0;
      const double a = dx * tx[l] + dy * ty[l] + dz * tz[l];
      const double kinetic = (dx * dx + dy * dy + dz * dz) * mass[l], extra = less[l] * a * a;
      across[l] = free ? kinetic : 0.0;
      lengthwise[l] = free ? extra : 0.0;
    }
  }
  else
  {
    // The same kinetic terms; the lengthwise ones are read only along a cable with added mass, and not written.
#pragma omp simd
    for (std::size_t l = 0; l <= m; ++l)
    {
      const double dx = x[l] - xt[l], dy = y[l] - yt[l], dz = z[l] - zt[l];
      const double kinetic = (dx * dx + dy * dy + dz * dz) * mass[l];
      across[l] = w[l] > 0.0 ? kinetic : 0.0;
    }
  }
  const double* __restrict c = law.c, * __restrict alpha = law.alpha, * __restrict kink = law.kink;
  const double* __restrict zero = law.zero, * __restrict dashpot = law.dashpot;
  if (!unilateral)
  {
#pragma omp simd
    for (std::size_t k = 0; k < m; ++k)
    {
      elastic[k] = 2.0 * (0.5 * c[k] * c[k] / alpha[k]);  // a rod's: C^2 / (2 alpha)
    }
  }
  else
  {
#pragma omp simd
    for (std::size_t k = 0; k < m; ++k)
    {
      // The integral of the law from where it is 0: max(C, 0)^2 / (2 alpha); with a middle piece
      // f(C) = kink / alpha + slope (C - kink), zero at z, the integral f(C)^2 / (2 slope) from z, and above
      // the kink that at the kink plus (C^2 - kink^2) / (2 alpha): continuous, as the line search needs.
      const double ck = c[k], a = alpha[k], bend = kink[k], d = dashpot[k], z = zero[k];
      const double taut = std::max(ck, 0.0);
      const bool damped = d > 0.0;
      const double slope = damped ? d : 1.0;  // kept from dividing by 0 where the piece is not used
      const bool above = ck >= bend;
      const double on_middle = above ? bend : std::max(ck, z);
      const double force = bend / a + slope * (on_middle - bend);
      const double middle = 0.5 * force * force / slope;
      const double line = 0.5 * (ck * ck - bend * bend) / a + middle;
      const double cable = 0.5 * taut * taut / a;
      const double damped_energy = above ? line : middle;
      elastic[k] = 2.0 * (damped ? damped_energy : cable);
    }
  }
  const double* __restrict cx = law.curve[0] + 2, * __restrict cy = law.curve[1] + 2;
  const double* __restrict cz = law.curve[2] + 2, * __restrict inv_gamma = law.inv_gamma;
  const std::size_t joints = bending && m > 0 ? m - 1 : 0;
#pragma omp simd
  for (std::size_t j = 0; j < joints; ++j)
  {
    bent[j] = (cx[j] * cx[j] + cy[j] * cy[j] + cz[j] * cz[j]) * inv_gamma[j];
  }
}

}  // namespace

void energyTerms(const PrimalNewton::Particles& p, const EnergyLaw& law, std::size_t m, bool along, bool unilateral,
                 bool bending, double* terms, std::size_t stride)
{
  energyTermsCloned(p, law, m, along, unilateral, bending, terms, stride);
}

double PrimalNewton::energy(const Cable& cable) const
{
  const std::size_t m = ws_.m;
  const std::size_t stride = energy_terms_.size() / 4;
  double* terms = energy_terms_.data();
  const EnergyLaw law{ws_.c.data(),        ws_.alpha.data(),   ws_.kink.data(),
                      ws_.zero.data(),     ws_.dashpot.data(), {curve_x_.data(), curve_y_.data(), curve_z_.data()},
                      ws_.inv_gamma.data()};
  energyTerms(particles(cable), law, m, cable.anisotropic, ws_.unilateral, ws_.bending, terms, stride);
  // Summed in a fixed order, whatever the vector width (sumOf).
  const double kinetic =
      sumOf(terms, nullptr, m + 1) + (cable.anisotropic ? sumOf(terms + stride, nullptr, m + 1) : 0.0);
  const double drum = ws_.drum != nullptr ? ws_.drum->energy(ws_.c[0]) : 0.0;  // the spool segment and the drum
  const std::size_t from = ws_.drum != nullptr ? 1 : 0;
  const double elastic = sumOf(terms + 2 * stride + from, nullptr, m > from ? m - from : 0) +
                         (ws_.bending && m >= 1 ? sumOf(terms + 3 * stride, nullptr, m - 1) : 0.0);
  return 0.5 * (kinetic + elastic) + drum;
}

double PrimalNewton::segmentForce(std::size_t k, double c) const
{
  if (k == 0 && ws_.drum != nullptr)
  {
    return ws_.drum->force(c);
  }
  return ws_.law(k, c);
}

bool PrimalNewton::solveModel(const Cable& cable, int* rounds)
{
  // The model: the step energy's second-order expansion in the positions, with each cable segment's
  // energy (1 / 2 alpha) max(C, 0)^2 expanded in its linearised stretch C + n . (dx_k+1 - dx_k), so a
  // segment is in the model when the step stretches it. That model is convex and piecewise quadratic; its
  // minimiser is found by active sets (solve, take in the segments the step stretches, let go of those it
  // does not, until the set holds), starting from the segments stretched now or taut at the end of the last
  // step (the set changes little from step to step). A rod's segments (bending stiffness) are always in it.
  const std::size_t m = ws_.m;
  const std::size_t rows = 3 * (m + 1);
  double* model = ws_.on();
  for (std::size_t k = 0; k < m && !model_unsettled_; ++k)
  {
    model[k] = !ws_.unilateral || ws_.c[k] > ws_.kink[k] || ws_.taut[ws_.first + k] ? 1.0 : 0.0;
    middle_[k] = onMiddle(k, model[k], ws_.c[k]);
  }
  double shift = 0.0;
  for (int round = 0;; ++round)
  {
    assemble(cable, whole_compression_);
    if (shift > 0.0)
    {
      shiftHessian(shift);
    }
    std::transform(grad_.begin(), grad_.begin() + static_cast<std::ptrdiff_t>(rows), step_.begin(),
                   [](double g) { return -g; });
    const double* second = ws_.bending ? hessian_second_.data() : nullptr;
    // The drum's law sets the spool segment's force from how particle 1 answers it. With the sweep and the
    // spool's particle pinned, one solve finds both (banded::solveBlockBandedPulled); otherwise a second
    // solve for a unit pull does (drumStep).
    const bool pulled = ws_.drum != nullptr && cable.inv_mass[ws_.first + 1] > 0.0;
    const bool in_one = pulled && linear_ == DirectSolver::LinearSolve::kSweep && cable.inv_mass[ws_.first] == 0.0;
    bool ok = false;
    if (in_one)
    {
      ok = pulledSolve(second);
    }
    else
    {
      ok = linear_ == DirectSolver::LinearSolve::kLapack
               ? banded::solveBlockBandedLapack(hessian_diag_.data(), hessian_first_.data(), second, step_.data(),
                                                m + 1, band_.data(), layout())
               : banded::solveBlockBanded(hessian_diag_.data(), hessian_first_.data(), second, step_.data(), m + 1,
                                          work_.data(), layout());
    }
    ++*rounds;
    if (!ok && whole_compression_)
    {
      // Not definite with every compressed segment's geometric stiffness whole: a rod buckling, or the
      // iterate's multipliers compressing it harder than the solution will. This round again with the
      // exact Hessian plus shift x each particle's mass (Levenberg-Marquardt), the shift doubling from
      // kFirstShift until it is definite; beyond kMaxShift, with each compressed segment's stiffness taking at
      // most kCompressedShare of its ends' masses, which is always definite.
      shift = shift > 0.0 ? 2.0 * shift : kFirstShift;
      whole_compression_ = shift <= kMaxShift;
      shift = whole_compression_ ? shift : 0.0;
      --round;
      continue;
    }
    if (!ok)
    {
      return false;
    }
    if (pulled && !in_one && !drumStep(second != nullptr))
    {
      return false;
    }
    std::size_t changes = 0;
    for (std::size_t k = ws_.drum != nullptr ? 1 : 0; ws_.unilateral && k < m; ++k)
    {
      const double stretch = linearStretch(k);
      const double now = stretch > ws_.kink[k] ? 1.0 : 0.0;
      const double middle = onMiddle(k, now, stretch);
      changes += now != model[k] || middle != middle_[k] ? 1 : 0;
      model[k] = now;
      middle_[k] = middle;
    }
    if (changes == 0 || round + 1 >= kMaxModelRounds)
    {
      // Still changing after the last round (a long slack run going taut a segment a round): the next
      // Newton iteration goes on from this model, not from the start again.
      model_unsettled_ = changes > 0;
      return true;
    }
  }
}

void PrimalNewton::shiftHessian(double shift)
{
  const std::size_t stride = lambda_.size();
  double* diag = hessian_diag_.data();
  for (std::size_t l = 0; l <= ws_.m; ++l)
  {
    const double add = shift * mass_[l];  // 0 for a pinned particle, whose row is the identity
    diag[l] += add, diag[4 * stride + l] += add, diag[8 * stride + l] += add;
  }
}

namespace
{

/// The drum's law as the pulled solve asks for it: particle 1 moving `along` n_0 stretches the spool segment
/// to c_0 + along, and its pull f takes compliance f off that.
class DrumLaw : public banded::EndLaw
{
 public:
  DrumLaw(const SpoolDrum& drum, double stretch) : drum_(drum), stretch_(stretch) {}
  double force(double along, double compliance) const override
  {
    return drum_.forceAgainst(stretch_ + along, std::max(compliance, 0.0));
  }

 private:
  const SpoolDrum& drum_;
  double stretch_;
};

}  // namespace

bool PrimalNewton::pulledSolve(const double* second)
{
  // The spool segment's force f pulls particle 1 along -n_0: the right-hand side gets -f n_0 there.
  const double pull[3] = {ws_.nx[0], ws_.ny[0], ws_.nz[0]};
  const DrumLaw law(*ws_.drum, ws_.c[0]);
  double drum_force = 0.0;
  if (!banded::solveBlockBandedPulled(hessian_diag_.data(), hessian_first_.data(), second, step_.data(), ws_.m + 1,
                                      work_.data(), pull, law, &drum_force, layout()))
  {
    return false;
  }
  lambda_step_[0] = drum_force - lambda_[0];
  return true;
}

bool PrimalNewton::drumStep(bool second)
{
  // The spool segment follows the drum's law: its force f pulls particle 1 along -n_0, so the step is
  // dx = p + f q (p the solve without it, q the answer to a unit pull), particle 1 moves n_0 . dx along
  // the segment, its stretch is a - b f, and f = drum.forceAgainst(a, b) meets the law exactly.
  const std::size_t m = ws_.m;
  const std::size_t rows = 3 * (m + 1);
  std::copy(step_.begin(), step_.begin() + static_cast<std::ptrdiff_t>(rows), grad_step_.begin());
  std::fill(step_.begin(), step_.begin() + static_cast<std::ptrdiff_t>(rows), 0.0);
  step_[3] = -ws_.nx[0], step_[4] = -ws_.ny[0], step_[5] = -ws_.nz[0];
  const bool again = linear_ == DirectSolver::LinearSolve::kLapack
                         ? banded::solveBlockBandedLapackAgain(second, step_.data(), m + 1, band_.data())
                         : (banded::solveBlockBandedAgain(second, step_.data(), m + 1, work_.data()), true);
  if (!again)
  {
    return false;
  }
  const double a = ws_.c[0] + ws_.nx[0] * grad_step_[3] + ws_.ny[0] * grad_step_[4] + ws_.nz[0] * grad_step_[5];
  const double b = -(ws_.nx[0] * step_[3] + ws_.ny[0] * step_[4] + ws_.nz[0] * step_[5]);
  const double drum_force = ws_.drum->forceAgainst(a, std::max(b, 0.0));
  for (std::size_t i = 0; i < rows; ++i)
  {
    step_[i] = grad_step_[i] + drum_force * step_[i];
  }
  lambda_step_[0] = drum_force - lambda_[0];
  return true;
}

[[gnu::always_inline]] inline double PrimalNewton::linearStretch(std::size_t k) const
{
  const double* a = &step_[3 * k];
  const double* b = &step_[3 * (k + 1)];
  return ws_.c[k] + ws_.nx[k] * (b[0] - a[0]) + ws_.ny[k] * (b[1] - a[1]) + ws_.nz[k] * (b[2] - a[2]);
}

[[gnu::always_inline]] inline double PrimalNewton::alongSegment(std::size_t k) const
{
  const double* a = &step_[3 * k];
  const double* b = &step_[3 * (k + 1)];
  return ws_.nx[k] * (b[0] - a[0]) + ws_.ny[k] * (b[1] - a[1]) + ws_.nz[k] * (b[2] - a[2]);
}

namespace
{

/// What multiplierSteps reads: the Newton step (3 a particle), each segment's stretch, direction, compliance,
/// law (kink, dashpot's slope) and whether it is in the model and on the middle piece, and its multiplier.
struct MultiplierLaw
{
  const double *step, *c, *nx, *ny, *nz, *alpha, *kink, *dashpot, *model, *middle, *lambda;
};

/// Each multiplier's Newton step into `out`, segments `from` to `count` - 1 (PrimalNewton::multiplierStep):
/// to the linearised force of its stretch C + n . (dx_k+1 - dx_k), by its law's piece in the model (the spring
/// over alpha, or the dashpot's middle piece), 0 out of it. Branch-free, so that it vectorises; the same
/// operations as linearStretch and middleForce. kUnilateral false (a rod's segments, all in the model): the
/// spring's alone.
template <bool kUnilateral>
ROV_TETHER_TARGET_CLONES void multiplierSteps(const MultiplierLaw& in, std::size_t from, std::size_t count,
                                              double* __restrict out)
{
  const double* __restrict step = in.step, * __restrict c = in.c, * __restrict nx = in.nx;
  const double* __restrict ny = in.ny, * __restrict nz = in.nz, * __restrict alpha = in.alpha;
  const double* __restrict kink = in.kink, * __restrict dashpot = in.dashpot, * __restrict model = in.model;
  const double* __restrict middle = in.middle, * __restrict lambda = in.lambda;
#pragma omp simd
  for (std::size_t k = from; k < count; ++k)
  {
    const double* a = step + 3 * k;
    const double* b = a + 3;
    const double stretch = c[k] + nx[k] * (b[0] - a[0]) + ny[k] * (b[1] - a[1]) + nz[k] * (b[2] - a[2]);
    const double a_k = alpha[k];
    const double spring = stretch / a_k;
    double target = spring;
    if constexpr (kUnilateral)
    {
      const double bend = kink[k], slope = dashpot[k];
      const double piece = bend / a_k + slope * (stretch - bend);
      const bool on_middle = slope > 0.0 && middle[k] > 0.0;
      const double off_model = on_middle ? piece : 0.0;
      target = model[k] > 0.0 ? spring : off_model;
    }
    out[k] = target - lambda[k];
  }
}

}  // namespace

void PrimalNewton::multiplierStep(const Cable& cable)
{
  // Each multiplier's Newton step: to the linearised force (C + n . (dx_k+1 - dx_k)) / alpha of a segment in
  // the model, to its dashpot's middle piece at that stretch for one on it, to 0 for one out of the model (the
  // drum's was set with its solve).
  const MultiplierLaw law{step_.data(),  ws_.c.data(),     ws_.nx.data(),   ws_.ny.data(),
                          ws_.nz.data(), ws_.alpha.data(), ws_.kink.data(), ws_.dashpot.data(),
                          ws_.on(),      middle_.data(),   lambda_.data()};
  const std::size_t from = ws_.drum != nullptr ? 1 : 0;
  ws_.unilateral ? multiplierSteps<true>(law, from, ws_.m, lambda_step_.data())
                 : multiplierSteps<false>(law, from, ws_.m, lambda_step_.data());
  if (ws_.drum != nullptr && !(cable.inv_mass[ws_.first + 1] > 0.0))
  {
    lambda_step_[0] = ws_.drum->force(ws_.c[0]) - lambda_[0];  // a segment nothing can move: the law alone
  }
}

double PrimalNewton::slope() const
{
  // The energy's slope along the step: the model's gradient, corrected where the model's force differs
  // from the energy's (a segment not stretched yet, whose energy is flat at 0; the drum's piece).
  const std::size_t rows = 3 * (ws_.m + 1);
  const double* model = ws_.on();
  double slope = sumOf(grad_.data(), step_.data(), rows);
  for (std::size_t k = 0; k < ws_.m; ++k)
  {
    double model_force = 0.0;
    if (k == 0 && ws_.drum != nullptr)
    {
      model_force = 0.0;  // the gradient left it out: add the law's force at the current stretch
    }
    else if (ws_.unilateral && model[k] > 0.0)
    {
      model_force = ws_.c[k] / ws_.alpha[k];
    }
    else if (inMiddle(k))
    {
      model_force = ws_.middleForce(k, ws_.c[k]);
    }
    else
    {
      continue;  // not in the model (nothing given), or a rod's (the model's force is the energy's)
    }
    slope -= (model_force - segmentForce(k, ws_.c[k])) * alongSegment(k);
  }
  return slope;
}

double PrimalNewton::step(Cable& cable, int* rounds)
{
  if (!solveModel(cable, rounds))
  {
    return std::numeric_limits<double>::infinity();
  }
  multiplierStep(cable);
  const std::size_t f = ws_.first;
  const double move = largestComponent(step_.data(), 3 * (ws_.m + 1)) / ws_.nominal;
  // The slope and the energy are for the line search, which a small move does without. The energy here is the
  // last accepted trial's when the line search computed it there.
  const bool search = move > kGlobalMove;
  const double along_step = search ? slope() : 0.0;
  const double before = search ? (energy_known_ ? known_energy_ : energy(cable)) : 0.0;
  energy_known_ = false;
  ws_.save(cable);
  double t = 1.0;
  for (int halving = 0;; ++halving)
  {
    for (std::size_t l = 0; l <= ws_.m; ++l)
    {
      cable.x[f + l] = ws_.sx[l] + t * step_[3 * l];
      cable.y[f + l] = ws_.sy[l] + t * step_[3 * l + 1];
      cable.z[f + l] = ws_.sz[l] + t * step_[3 * l + 2];
    }
    ws_.geometry(cable);
    curvature(cable);
    // Near the solution Newton's step is taken whole (quadratic convergence); far from it, the step is
    // halved until the energy falls as the slope promises (Armijo).
    bool accept = !search || halving == kMaxHalvings || !(along_step < 0.0);
    if (!accept)
    {
      known_energy_ = energy(cable);
      accept = known_energy_ <= before + kArmijo * t * along_step;
      energy_known_ = accept;
    }
    if (accept)
    {
      for (std::size_t k = 0; k < ws_.m; ++k)
      {
        lambda_[k] += t * lambda_step_[k];
      }
      return t * move;
    }
    t *= 0.5;
  }
}

namespace
{

/// What segmentResiduals reads: each segment's stretch, law and multiplier, whether it is in the model, and its
/// particles' inverse masses and direction.
struct SegmentLaw
{
  const double *c, *alpha, *kink, *zero, *dashpot, *inv_rest, *model, *lambda, *w, *nx, *ny, *nz;
};

/// Each of `count` segments' pull lambda n into `pull` (segment k at k + 1), and the largest residual of the
/// segments from `from` on, relative to their rest length: C - alpha lambda of one in the model (a rod's are all
/// in it); of a cable's out of it, max(C, 0) (or, with the dashpot's middle piece, how far past the kink) plus
/// the move lambda against its law would make. Branch-free, so that it vectorises. kUnilateral false (a rod's
/// segments, all in the model): only the first, and the cable's law is not computed.
template <bool kUnilateral>
ROV_TETHER_TARGET_CLONES double segmentResiduals(const SegmentLaw& in, double* const* pull, std::size_t count,
                                                 std::size_t from)
{
  const double* __restrict c = in.c, * __restrict alpha = in.alpha, * __restrict kink = in.kink;
  const double* __restrict zero = in.zero, * __restrict dashpot = in.dashpot, * __restrict inv_rest = in.inv_rest;
  const double* __restrict model = in.model, * __restrict lambda = in.lambda, * __restrict w = in.w;
  const double* __restrict nx = in.nx, * __restrict ny = in.ny, * __restrict nz = in.nz;
  double* __restrict px = pull[0] + 1, * __restrict py = pull[1] + 1, * __restrict pz = pull[2] + 1;
  double worst = 0.0;
#pragma omp simd reduction(max : worst)
  for (std::size_t k = 0; k < count; ++k)
  {
    const double lam = lambda[k], stretch = c[k], a = alpha[k];
    px[k] = lam * nx[k], py[k] = lam * ny[k], pz[k] = lam * nz[k];
    const double in_model = std::abs(stretch - a * lam);
    double r = in_model;
    if constexpr (kUnilateral)
    {
      const double bend = kink[k], slope = dashpot[k];
      const double mobility = w[k] + w[k + 1];
      // The law's force at C (DirectWorkspace::law, a cable's): above the kink max(C, 0) / alpha, then the
      // middle piece down to where it is 0, then 0.
      const double middle = bend / a + slope * (stretch - bend);
      const double force = stretch >= bend ? std::max(stretch, 0.0) / a : (stretch > zero[k] ? middle : 0.0);
      const double damped = std::max(stretch - bend, 0.0) + std::abs(lam - force) * mobility;
      const double slack = std::max(stretch, 0.0) + std::abs(lam) * mobility;
      r = model[k] > 0.0 ? in_model : (slope > 0.0 ? damped : slack);
    }
    const double relative = k >= from ? r * inv_rest[k] : 0.0;
    worst = std::max(worst, relative);
  }
  return worst;
}

/// What largestMove reads, by particle: inverse masses (across, and along the cable), masses, positions and
/// predictions, tangents (with added mass), the segments' pulls (segmentResiduals', segment l - 1 at l) and the
/// bending joints' terms (prepareBending's, as the assembly reads them).
struct ParticleForces
{
  PrimalNewton::Particles p;
  const double* w_along;
  const double* pull[3];
  const double *bend_pull[3], *curve[3];
  /// With bending, where the first loop leaves each particle's force before the joints' terms (rows long each).
  double* partial[3];
};

/// The move a force (f0, f1, f2) makes a particle of largest inverse mass `inverse` (0 pinned: none).
ROV_TETHER_INLINE double moveOf(double inverse, double f0, double f1, double f2)
{
  return inverse > 0.0 ? inverse * std::sqrt(f0 * f0 + f1 * f1 + f2 * f2) : 0.0;
}

/// The largest move a free particle's force balance M (x - x~) + J^T lambda + the bending terms would make: the
/// force times the particle's largest inverse mass. Its terms in the order the step's equations add them: the
/// mass, segment l - 1's pull, segment l's, then the joints l - 2, l - 1, l.
/// Along (added mass) and bending are template arguments: a loop-invariant test in the loop let GCC split it
/// into versions, of which the bending one stayed scalar. With bending, the joints' terms and the largest move
/// are a second loop over the first's forces (in.partial): the one loop read more arrays than the processor has
/// registers for their addresses, as the assembly's did (bendingRowsAdded).
template <bool kAlong, bool kBending>
ROV_TETHER_TARGET_CLONES double largestMove(const ParticleForces& in, std::size_t rows)
{
  constexpr bool along = kAlong;
  const double* __restrict w = in.p.w, * __restrict w_along = in.w_along, * __restrict mass = in.p.mass;
  const double* __restrict less = in.p.less, * __restrict x = in.p.x, * __restrict y = in.p.y;
  const double* __restrict z = in.p.z, * __restrict xt = in.p.xt, * __restrict yt = in.p.yt, * __restrict zt = in.p.zt;
  const double* __restrict tx = along ? in.p.tx : in.p.x, * __restrict ty = along ? in.p.ty : in.p.y;
  const double* __restrict tz = along ? in.p.tz : in.p.z;
  const double* __restrict px = in.pull[0], * __restrict py = in.pull[1], * __restrict pz = in.pull[2];
  double* __restrict s0 = in.partial[0], * __restrict s1 = in.partial[1], * __restrict s2 = in.partial[2];
  double worst = 0.0;
#pragma omp simd reduction(max : worst)
  for (std::size_t l = 0; l < rows; ++l)
  {
    const double d0 = x[l] - xt[l], d1 = y[l] - yt[l], d2 = z[l] - zt[l];
    const double m = mass[l];
    double f0 = d0 * m, f1 = d1 * m, f2 = d2 * m;
    if constexpr (kAlong)
    {
      const double t0 = tx[l], t1 = ty[l], t2 = tz[l];
      const double a = less[l] * (d0 * t0 + d1 * t1 + d2 * t2);
      f0 += a * t0, f1 += a * t1, f2 += a * t2;
    }
    f0 += px[l], f1 += py[l], f2 += pz[l];
    f0 -= px[l + 1], f1 -= py[l + 1], f2 -= pz[l + 1];
    if constexpr (kBending)
    {
      s0[l] = f0, s1[l] = f1, s2[l] = f2;
    }
    else
    {
      worst = std::max(worst, moveOf(std::max(w[l], w_along[l]), f0, f1, f2));
    }
  }
  if constexpr (kBending)
  {
    const double* __restrict p0 = in.bend_pull[0], * __restrict p1 = in.bend_pull[1];
    const double* __restrict p2 = in.bend_pull[2];
    const double* __restrict cx = in.curve[0], * __restrict cy = in.curve[1], * __restrict cz = in.curve[2];
#pragma omp simd reduction(max : worst)
    for (std::size_t l = 0; l < rows; ++l)
    {
      double f0 = s0[l], f1 = s1[l], f2 = s2[l];
      addJointPulls(p0, p1, p2, cx, cy, cz, l, f0, f1, f2);
      worst = std::max(worst, moveOf(std::max(w[l], w_along[l]), f0, f1, f2));
    }
  }
  return worst;
}

}  // namespace

bool PrimalNewton::segmentAbove(double tolerance) const
{
  // Every 8th segment's |C - alpha lambda| over its rest length, as segmentResiduals<false> computes it.
  for (std::size_t k = ws_.drum != nullptr ? 1 : 0; k < ws_.m; k += 8)
  {
    if (std::abs(ws_.c[k] - ws_.alpha[k] * lambda_[k]) * ws_.inv_rest[k] > tolerance)
    {
      return true;
    }
  }
  return false;
}

double PrimalNewton::residual(const Cable& cable)
{
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  // Each segment's equation, and its pull lambda n, into segment_'s first three arrays (segment k at k + 1, 0
  // before the first and after the last): segment_ is free between assemblies.
  const bool drum = ws_.drum != nullptr;
  double* pull[3] = {segmentArray(0), segmentArray(1), segmentArray(2)};
  const double* w = cable.inv_mass.data() + f;
  const SegmentLaw law{ws_.c.data(),    ws_.alpha.data(),   ws_.kink.data(),
                       ws_.zero.data(), ws_.dashpot.data(), ws_.inv_rest.data(),
                       ws_.on(),        lambda_.data(),     w,
                       ws_.nx.data(),   ws_.ny.data(),      ws_.nz.data()};
  double worst = ws_.unilateral ? segmentResiduals<true>(law, pull, m, drum ? 1 : 0)
                                : segmentResiduals<false>(law, pull, m, drum ? 1 : 0);
  if (drum)
  {
    worst = std::max(worst, ws_.drumResidual(lambda_[0], w[0] + w[1]));  // the spool segment (left out above)
  }
  for (double* v : pull)
  {
    v[0] = v[m + 1] = 0.0;
  }
  // Each free particle's force balance M (x - x~) + J^T lambda + the bending terms, as a displacement: times
  // its largest inverse mass (along the cable, where added mass does not act), over the nominal segment,
  // divided once after the largest is found (dividing by a positive number keeps the order, so this is the
  // largest of the quotients, bit for bit).
  const ParticleForces forces{particles(cable),
                              cable.anisotropic ? cable.inv_mass_along.data() + f : w,
                              {pull[0], pull[1], pull[2]},
                              {term(bend_pull_, 0), term(bend_pull_, 1), term(bend_pull_, 2)},
                              {curve_x_.data(), curve_y_.data(), curve_z_.data()},
                              {segmentArray(3), segmentArray(4), segmentArray(5)}};
  const bool along = cable.anisotropic;
  const double worst_move =
      along ? (ws_.bending ? largestMove<true, true>(forces, m + 1) : largestMove<true, false>(forces, m + 1))
            : (ws_.bending ? largestMove<false, true>(forces, m + 1) : largestMove<false, false>(forces, m + 1));
  return std::max(worst, worst_move / ws_.nominal);
}

}  // namespace rov_tether
