// The direct solver's primal path: Newton on the positions with the step energy's full Hessian (geometric
// stiffness and EI bending included), a banded SPD solve and a backtracking line search. See
// direct_solver.hpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "rov_tether/banded.hpp"
#include "rov_tether/direct_solver.hpp"

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
/// The most a compressed segment's geometric stiffness may take off either end's mass in the Hessian: an
/// eighth, so a particle's two segments take at most 2 x 2 / 8 of it (a segment's block enters its two
/// particles as [1 -1; -1 1], eigenvalue 2).
constexpr double kCompressedShare = 0.125;

/// Joint curvature C_b = a x_p - (a + b) x_p+1 + b x_p+2 at the joint after particle p (each axis; a and b
/// the inverse rest lengths of its two segments), and its weights g = (a, -(a + b), b): linear in the
/// positions. The energy, its gradient and Hessian, and the force residual all read it from here.
struct JointCurvature
{
  double g[3];
  double c[3];
};

JointCurvature jointCurvature(const Cable& cable, std::size_t p)
{
  const double a = 1.0 / cable.rest[p];
  const double b = 1.0 / cable.rest[p + 1];
  return {{a, -(a + b), b},
          {a * cable.x[p] - (a + b) * cable.x[p + 1] + b * cable.x[p + 2],
           a * cable.y[p] - (a + b) * cable.y[p + 1] + b * cable.y[p + 2],
           a * cable.z[p] - (a + b) * cable.z[p + 1] + b * cable.z[p + 2]}};
}

/// Adds v times the 3x3 block `b` (row-major) to `target`.
inline void addTo(double* target, const double* b, double v = 1.0)
{
  for (std::size_t i = 0; i < 9; ++i)
  {
    target[i] += v * b[i];
  }
}

}  // namespace

double DirectSolver::energy(const Cable& cable) const
{
  const std::size_t f = first_;
  double kinetic = 0.0;
  for (std::size_t l = 0; l <= m_; ++l)
  {
    const double w = cable.inv_mass[f + l];
    if (w > 0.0)
    {
      const double dx = cable.x[f + l] - xt_[l];
      const double dy = cable.y[f + l] - yt_[l];
      const double dz = cable.z[f + l] - zt_[l];
      kinetic += (dx * dx + dy * dy + dz * dz) / w;
      if (cable.anisotropic)
      {
        // M = m_across I + (m_along - m_across) t t^T.
        const double along = dx * cable.tx[f + l] + dy * cable.ty[f + l] + dz * cable.tz[f + l];
        kinetic += (1.0 / cable.inv_mass_along[f + l] - 1.0 / w) * along * along;
      }
    }
  }
  double elastic = 0.0;
  double drum = 0.0;
  for (std::size_t k = 0; k < m_; ++k)
  {
    if (k == 0 && drum_ != nullptr)
    {
      drum = drum_->energy(c_[0]);  // the spool segment and the drum in series
      continue;
    }
    const double c = unilateral_ ? std::max(c_[k], 0.0) : c_[k];
    elastic += c * c / alpha_[k];
  }
  for (std::size_t j = 0; bending_ && j + 1 < m_; ++j)
  {
    const JointCurvature joint = jointCurvature(cable, f + j);
    const double* cb = joint.c;
    elastic += (cb[0] * cb[0] + cb[1] * cb[1] + cb[2] * cb[2]) / gamma_[j];
  }
  return 0.5 * (kinetic + elastic) + drum;
}

double DirectSolver::segmentForce(std::size_t k, double c) const
{
  if (k == 0 && drum_ != nullptr)
  {
    return drum_->force(c);
  }
  return (unilateral_ ? std::max(c, 0.0) : c) / alpha_[k];
}

void DirectSolver::assemblePrimal(const Cable& cable)
{
  // The Hessian by 3x3 blocks of particles: diagonal (l, l), first below (l + 1, l), second below (l + 2, l,
  // with bending). A pinned particle's row is the identity, and nothing couples to it.
  const std::size_t f = first_;
  const std::size_t m = m_;
  const std::size_t blocks = m + 1;
  std::fill(hessian_diag_.begin(), hessian_diag_.begin() + static_cast<std::ptrdiff_t>(9 * blocks), 0.0);
  std::fill(hessian_first_.begin(), hessian_first_.begin() + static_cast<std::ptrdiff_t>(9 * blocks), 0.0);
  std::fill(hessian_second_.begin(), hessian_second_.begin() + static_cast<std::ptrdiff_t>(9 * blocks), 0.0);
  std::fill(grad_.begin(), grad_.begin() + static_cast<std::ptrdiff_t>(3 * blocks), 0.0);
  const double* w = cable.inv_mass.data() + f;
  auto pinned = [w](std::size_t l) { return w[l] == 0.0; };
  // A particle's largest inverse mass (along the cable, where added mass does not act).
  auto mobility = [&](std::size_t l) { return cable.anisotropic ? std::max(w[l], cable.inv_mass_along[f + l]) : w[l]; };
  static constexpr double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (std::size_t l = 0; l <= m; ++l)
  {
    if (pinned(l))
    {
      addTo(&hessian_diag_[9 * l], kIdentity);
      continue;
    }
    // The particle's mass matrix: m_across I, plus (m_along - m_across) t t^T with added mass.
    const double mass = 1.0 / w[l];
    double block[9] = {mass, 0, 0, 0, mass, 0, 0, 0, mass};
    if (cable.anisotropic)
    {
      const double t[3] = {cable.tx[f + l], cable.ty[f + l], cable.tz[f + l]};
      const double less = 1.0 / cable.inv_mass_along[f + l] - mass;
      for (std::size_t a = 0; a < 3; ++a)
      {
        for (std::size_t c = 0; c < 3; ++c)
        {
          block[3 * a + c] += less * t[a] * t[c];
        }
      }
    }
    const double d[3] = {cable.x[f + l] - xt_[l], cable.y[f + l] - yt_[l], cable.z[f + l] - zt_[l]};
    for (std::size_t a = 0; a < 3; ++a)
    {
      grad_[3 * l + a] = block[3 * a] * d[0] + block[3 * a + 1] * d[1] + block[3 * a + 2] * d[2];
    }
    addTo(&hessian_diag_[9 * l], block);
  }
  const double* model = on();
  for (std::size_t k = 0; k < m; ++k)
  {
    // The segments of the model: all of a rod's; of a cable's, those the step stretches (primalStep); the
    // spool segment on the drum's piece.
    double lam = c_[k] / alpha_[k];
    double axial = 1.0 / alpha_[k];
    if (k == 0 && drum_ != nullptr)
    {
      // The spool segment's force is the drum's law, solved for in primalStep: here only its geometric
      // stiffness.
      lam = 0.0;
      axial = 0.0;
    }
    else if (!(model[k] > 0.0))
    {
      continue;
    }
    const double n[3] = {nx_[k], ny_[k], nz_[k]};
    // dC/dx_k = -n, dC/dx_k+1 = +n: the gradient gets J^T lambda.
    for (std::size_t a = 0; a < 3; ++a)
    {
      grad_[3 * k + a] -= lam * n[a];
      grad_[3 * (k + 1) + a] += lam * n[a];
    }
    // Hessian of the segment's energy: axial (1 / alpha) n n^T plus the geometric stiffness
    // lambda / |d| (I - n n^T) of the Newton estimate of lambda (not C / alpha, which a stiff segment's
    // rounding makes useless). In compression it is negative: kept while it is at most kCompressedShare of
    // the mass of either end (then each particle's two segments take at most half its mass off the
    // Hessian's smallest eigenvalue, which stays positive), dropped beyond (a rod buckling). Dropped always,
    // a cable lying slack on a seabed converged linearly: 4 iterations a step instead of 2.
    double geometric = len_[k] > 0.0 ? primal_lambda_[k] / len_[k] : 0.0;
    if (geometric < 0.0 && !(-geometric * std::max(mobility(k), mobility(k + 1)) <= kCompressedShare))
    {
      geometric = 0.0;
    }
    double block[9];
    for (std::size_t a = 0; a < 3; ++a)
    {
      for (std::size_t c = 0; c < 3; ++c)
      {
        block[3 * a + c] = (axial - geometric) * n[a] * n[c] + (a == c ? geometric : 0.0);
      }
    }
    if (!pinned(k))
    {
      addTo(&hessian_diag_[9 * k], block);
    }
    if (!pinned(k + 1))
    {
      addTo(&hessian_diag_[9 * (k + 1)], block);
    }
    if (!pinned(k) && !pinned(k + 1))
    {
      addTo(&hessian_first_[9 * k], block, -1.0);
    }
  }
  for (std::size_t j = 0; bending_ && j + 1 < m; ++j)
  {
    // C_b is linear in the positions, so its Hessian is constant.
    const JointCurvature joint = jointCurvature(cable, f + j);
    const double* g = joint.g;
    const double* cb = joint.c;
    const double inv = 1.0 / gamma_[j];
    for (std::size_t r = 0; r < 3; ++r)
    {
      if (pinned(j + r))
      {
        continue;
      }
      for (std::size_t axis = 0; axis < 3; ++axis)
      {
        grad_[3 * (j + r) + axis] += g[r] * cb[axis] * inv;
      }
      for (std::size_t s = 0; s <= r; ++s)
      {
        if (pinned(j + s))
        {
          continue;
        }
        std::vector<double>& target = r == s ? hessian_diag_ : r == s + 1 ? hessian_first_ : hessian_second_;
        addTo(&target[9 * (j + s)], kIdentity, g[r] * g[s] * inv);
      }
    }
  }
  for (std::size_t l = 0; l <= m; ++l)
  {
    if (pinned(l))
    {
      grad_[3 * l] = grad_[3 * l + 1] = grad_[3 * l + 2] = 0.0;
    }
  }
}

double DirectSolver::primalStep(Cable& cable)
{
  const std::size_t f = first_;
  const std::size_t m = m_;
  const std::size_t rows = 3 * (m + 1);
  // The model: the step energy's second-order expansion in the positions, with each cable segment's
  // energy (1 / 2 alpha) max(C, 0)^2 expanded in its linearised stretch C + n . (dx_k+1 - dx_k), so a
  // segment is in the model when the step stretches it. That model is convex and piecewise quadratic; its
  // minimiser is found by active sets (solve, take in the segments the step stretches, let go of those it
  // does not, until the set holds), starting from the segments stretched now or taut at the end of the last
  // step (the set changes little from step to step). A rod's segments (bending stiffness) are always in it.
  double* model = on();
  for (std::size_t k = 0; k < m; ++k)
  {
    model[k] = !unilateral_ || c_[k] > 0.0 || taut_[first_ + k] ? 1.0 : 0.0;
  }
  for (int round = 0;; ++round)
  {
    assemblePrimal(cable);
    std::transform(grad_.begin(), grad_.begin() + static_cast<std::ptrdiff_t>(rows), step_.begin(),
                   [](double g) { return -g; });
    const double* second = bending_ ? hessian_second_.data() : nullptr;
    const bool ok = linear_ == LinearSolve::kLapack
                        ? banded::solveBlockBandedLapack(hessian_diag_.data(), hessian_first_.data(), second,
                                                         step_.data(), m + 1, band_.data())
                        : banded::solveBlockBanded(hessian_diag_.data(), hessian_first_.data(), second, step_.data(),
                                                   m + 1, work_.data());
    ++active_set_rounds_;
    if (!ok)
    {
      return std::numeric_limits<double>::infinity();
    }
    if (drum_ != nullptr && cable.inv_mass[f + 1] > 0.0)
    {
      // The spool segment follows the drum's law: its force f pulls particle 1 along -n_0, so the step is
      // dx = p + f q (p the solve without it, q the answer to a unit pull), particle 1 moves n_0 . dx along
      // the segment, its stretch is a - b f, and f = drum.forceAgainst(a, b) meets the law exactly.
      std::copy(step_.begin(), step_.begin() + static_cast<std::ptrdiff_t>(rows), grad_step_.begin());
      std::fill(step_.begin(), step_.begin() + static_cast<std::ptrdiff_t>(rows), 0.0);
      step_[3] = -nx_[0], step_[4] = -ny_[0], step_[5] = -nz_[0];
      const bool again =
          linear_ == LinearSolve::kLapack
              ? banded::solveBlockBandedLapackAgain(second != nullptr, step_.data(), m + 1, band_.data())
              : (banded::solveBlockBandedAgain(second != nullptr, step_.data(), m + 1, work_.data()), true);
      if (!again)
      {
        return std::numeric_limits<double>::infinity();
      }
      const double a = c_[0] + nx_[0] * grad_step_[3] + ny_[0] * grad_step_[4] + nz_[0] * grad_step_[5];
      const double b = -(nx_[0] * step_[3] + ny_[0] * step_[4] + nz_[0] * step_[5]);
      const double drum_force = drum_->forceAgainst(a, std::max(b, 0.0));
      for (std::size_t i = 0; i < rows; ++i)
      {
        step_[i] = grad_step_[i] + drum_force * step_[i];
      }
      lambda_step_[0] = drum_force - primal_lambda_[0];
    }
    std::size_t changes = 0;
    for (std::size_t k = drum_ != nullptr ? 1 : 0; unilateral_ && k < m; ++k)
    {
      const double* a = &step_[3 * k];
      const double* b = &step_[3 * (k + 1)];
      const double stretch = c_[k] + nx_[k] * (b[0] - a[0]) + ny_[k] * (b[1] - a[1]) + nz_[k] * (b[2] - a[2]);
      const double now = stretch > 0.0 ? 1.0 : 0.0;
      changes += now != model[k] ? 1 : 0;
      model[k] = now;
    }
    if (changes == 0 || round + 1 >= kMaxModelRounds)
    {
      break;
    }
  }
  // Each multiplier's Newton step: to the linearised force (C + n . (dx_k+1 - dx_k)) / alpha of a segment in
  // the model, to 0 for one out of it (the drum's was set with its solve).
  for (std::size_t k = drum_ != nullptr ? 1 : 0; k < m; ++k)
  {
    const double* a = &step_[3 * k];
    const double* b = &step_[3 * (k + 1)];
    const double stretch = c_[k] + nx_[k] * (b[0] - a[0]) + ny_[k] * (b[1] - a[1]) + nz_[k] * (b[2] - a[2]);
    lambda_step_[k] = (model[k] > 0.0 ? stretch / alpha_[k] : 0.0) - primal_lambda_[k];
  }
  if (drum_ != nullptr && !(cable.inv_mass[f + 1] > 0.0))
  {
    lambda_step_[0] = drum_->force(c_[0]) - primal_lambda_[0];  // a segment nothing can move: the law alone
  }
  // The energy's slope along the step: the model's gradient, corrected where the model's force differs
  // from the energy's (a segment not stretched yet, whose energy is flat at 0; the drum's piece).
  double slope = 0.0;
  double largest = 0.0;
  for (std::size_t i = 0; i < rows; ++i)
  {
    slope += grad_[i] * step_[i];
    largest = std::max(largest, std::abs(step_[i]));
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    double model_force = 0.0;
    if (k == 0 && drum_ != nullptr)
    {
      model_force = 0.0;  // the gradient left it out: add the law's force at the current stretch
    }
    else if (unilateral_ && model[k] > 0.0)
    {
      model_force = c_[k] / alpha_[k];
    }
    else
    {
      continue;  // not in the model (nothing given), or a rod's (the model's force is the energy's)
    }
    const double* a = &step_[3 * k];
    const double* b = &step_[3 * (k + 1)];
    slope -= (model_force - segmentForce(k, c_[k])) *
             (nx_[k] * (b[0] - a[0]) + ny_[k] * (b[1] - a[1]) + nz_[k] * (b[2] - a[2]));
  }
  const double move = largest / nominal_;
  const double before = move > kGlobalMove ? energy(cable) : 0.0;
  save(cable);
  double t = 1.0;
  for (int halving = 0;; ++halving)
  {
    for (std::size_t l = 0; l <= m; ++l)
    {
      cable.x[f + l] = sx_[l] + t * step_[3 * l];
      cable.y[f + l] = sy_[l] + t * step_[3 * l + 1];
      cable.z[f + l] = sz_[l] + t * step_[3 * l + 2];
    }
    geometry(cable);
    // Near the solution Newton's step is taken whole (quadratic convergence); far from it, the step is
    // halved until the energy falls as the slope promises (Armijo).
    if (move <= kGlobalMove || halving == kMaxHalvings || !(slope < 0.0) ||
        energy(cable) <= before + kArmijo * t * slope)
    {
      for (std::size_t k = 0; k < m; ++k)
      {
        primal_lambda_[k] += t * lambda_step_[k];
      }
      return t * move;
    }
    t *= 0.5;
  }
}

double DirectSolver::primalResidual(const Cable& cable) const
{
  const std::size_t f = first_;
  const std::size_t m = m_;
  const double* model = on_.data() + 1;
  // Each free particle's force balance M (x - x~) + J^T lambda + the bending terms, accumulated per axis in
  // grad_step_ (free here: primalStep refills it before use).
  double* force = const_cast<double*>(grad_step_.data());
  double worst = 0.0;
  for (std::size_t l = 0; l <= m; ++l)
  {
    const double w = cable.inv_mass[f + l];
    const double d[3] = {cable.x[f + l] - xt_[l], cable.y[f + l] - yt_[l], cable.z[f + l] - zt_[l]};
    for (std::size_t a = 0; a < 3; ++a)
    {
      force[3 * l + a] = w > 0.0 ? d[a] / w : 0.0;
    }
    if (w > 0.0 && cable.anisotropic)
    {
      const double t[3] = {cable.tx[f + l], cable.ty[f + l], cable.tz[f + l]};
      const double along = (1.0 / cable.inv_mass_along[f + l] - 1.0 / w) * (d[0] * t[0] + d[1] * t[1] + d[2] * t[2]);
      for (std::size_t a = 0; a < 3; ++a)
      {
        force[3 * l + a] += along * t[a];
      }
    }
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    const double lam = primal_lambda_[k];
    const double n[3] = {nx_[k], ny_[k], nz_[k]};
    for (std::size_t a = 0; a < 3; ++a)
    {
      force[3 * k + a] -= lam * n[a];
      force[3 * (k + 1) + a] += lam * n[a];
    }
    double r = 0.0;
    if (k == 0 && drum_ != nullptr)
    {
      r = std::abs(lam - drum_->force(c_[0])) * (cable.inv_mass[f] + cable.inv_mass[f + 1]);
    }
    else if (!unilateral_ || model[k] > 0.0)
    {
      r = std::abs(c_[k] - alpha_[k] * lam);
    }
    else
    {
      r = std::max(c_[k], 0.0) + std::abs(lam) * (cable.inv_mass[f + k] + cable.inv_mass[f + k + 1]);
    }
    worst = std::max(worst, r * inv_rest_[k]);
  }
  for (std::size_t j = 0; bending_ && j + 1 < m; ++j)
  {
    const JointCurvature joint = jointCurvature(cable, f + j);
    const double* g = joint.g;
    const double* cb = joint.c;
    for (std::size_t r = 0; r < 3; ++r)
    {
      for (std::size_t axis = 0; axis < 3; ++axis)
      {
        force[3 * (j + r) + axis] += g[r] * cb[axis] / gamma_[j];
      }
    }
  }
  for (std::size_t l = 0; l <= m; ++l)
  {
    // As a displacement: times the largest inverse mass (along the cable, where added mass does not act).
    const double w = std::max(cable.inv_mass[f + l], cable.anisotropic ? cable.inv_mass_along[f + l] : 0.0);
    if (w > 0.0)
    {
      const double* r = &force[3 * l];
      worst = std::max(worst, w * std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) / nominal_);
    }
  }
  return worst;
}

}  // namespace rov_tether
