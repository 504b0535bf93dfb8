#include "rov_tether/direct_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "rov_tether/banded.hpp"
#include "rov_tether/simd.hpp"

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
/// Rounds of active-set changes on one linearisation.
constexpr int kMaxActiveSetRounds = 30;

/// Unit vector n_k, length |d_k| and C_k = |d_k| - L_k of each of m segments.
ROV_TETHER_TARGET_CLONES void segmentGeometry(const double* __restrict x, const double* __restrict y,
                                              const double* __restrict z, const double* __restrict rest,
                                              double* __restrict nx, double* __restrict ny, double* __restrict nz,
                                              double* __restrict len, double* __restrict c, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    const double dx = x[k + 1] - x[k];
    const double dy = y[k + 1] - y[k];
    const double dz = z[k + 1] - z[k];
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double inv = 1.0 / (length + 1e-300);  // a zero-length segment has n = 0
    nx[k] = dx * inv, ny[k] = dy * inv, nz[k] = dz * inv;
    len[k] = length;
    c[k] = length - rest[k];
  }
}

/// The primal-dual active set at the current iterate and the largest relative constraint residual: a
/// segment that a free particle can move pulls when lambda + c (C - alpha lambda) > 0, c = 1 / (w_a + w_b)
/// its effective mass. At the solution an active segment has C = alpha lambda with lambda > 0, an inactive
/// one lambda = 0 with C <= 0; an inactive one still holding lambda has the residual lambda (w_a + w_b) / L.
ROV_TETHER_TARGET_CLONES double activeSet(const double* __restrict w, const double* __restrict inv_rest,
                                          const double* __restrict c, const double* __restrict alpha,
                                          const double* __restrict lam, double* __restrict on, std::size_t m)
{
  double worst = 0.0;
#pragma omp simd reduction(max : worst)
  for (std::size_t k = 0; k < m; ++k)
  {
    const double r = c[k] - alpha[k] * lam[k];
    const double mobility = w[k] + w[k + 1];  // 0: both ends pinned
    const double a = ((mobility > 0.0) & (lam[k] * mobility + r > 0.0)) ? 1.0 : 0.0;
    on[k] = a;
    const double residual = (a * std::abs(r) + (1.0 - a) * std::abs(lam[k]) * mobility) * inv_rest[k];
    worst = residual > worst ? residual : worst;
  }
  return worst;
}

/// Every row as if active, (J W J^T + alpha) dlambda = C - alpha lambda: its diagonal, right-hand side,
/// and its coupling to the next row, -w_k+1 n_k . n_k+1 (0 after the last).
ROV_TETHER_TARGET_CLONES void activeRows(const double* __restrict w, const double* __restrict alpha,
                                         const double* __restrict c, const double* __restrict lam,
                                         const double* __restrict nx, const double* __restrict ny,
                                         const double* __restrict nz, double* __restrict diag, double* __restrict rhs,
                                         double* __restrict coupling, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    diag[k] = w[k] + w[k + 1] + alpha[k];
    rhs[k] = c[k] - alpha[k] * lam[k];
  }
  for (std::size_t k = 0; k + 1 < m; ++k)
  {
    coupling[k] = -w[k + 1] * (nx[k] * nx[k + 1] + ny[k] * ny[k + 1] + nz[k] * nz[k + 1]);
  }
  coupling[m - 1] = 0.0;
}

/// activeRows with a mass that is larger across the cable than along it (added mass): each particle's
/// inverse mass is W_l = w_l I + dw_l t_l t_l^T (dw = w_along - w_across, t the tangent), so a row's
/// entries are n_k . W n_j = w (n_k . n_j) + dw (n_k . t)(n_j . t).
ROV_TETHER_TARGET_CLONES void activeRowsAnisotropic(const double* __restrict w, const double* __restrict dw,
                                                    const double* __restrict tx, const double* __restrict ty,
                                                    const double* __restrict tz, const double* __restrict alpha,
                                                    const double* __restrict c, const double* __restrict lam,
                                                    const double* __restrict nx, const double* __restrict ny,
                                                    const double* __restrict nz, double* __restrict diag,
                                                    double* __restrict rhs, double* __restrict coupling, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    const double a = nx[k] * tx[k] + ny[k] * ty[k] + nz[k] * tz[k];              // n_k . t_k
    const double b = nx[k] * tx[k + 1] + ny[k] * ty[k + 1] + nz[k] * tz[k + 1];  // n_k . t_k+1
    diag[k] = w[k] + w[k + 1] + dw[k] * a * a + dw[k + 1] * b * b + alpha[k];
    rhs[k] = c[k] - alpha[k] * lam[k];
  }
  for (std::size_t k = 0; k + 1 < m; ++k)
  {
    const double b = nx[k] * tx[k + 1] + ny[k] * ty[k + 1] + nz[k] * tz[k + 1];              // n_k . t_k+1
    const double e = nx[k + 1] * tx[k + 1] + ny[k + 1] * ty[k + 1] + nz[k + 1] * tz[k + 1];  // n_k+1 . t_k+1
    coupling[k] = -(w[k + 1] * (nx[k] * nx[k + 1] + ny[k] * ny[k + 1] + nz[k] * nz[k + 1]) + dw[k + 1] * b * e);
  }
  coupling[m - 1] = 0.0;
}

/// The system for the active set `on`: an active row as in activeRows, an inactive one lets go of its
/// multiplier (dlambda = -lambda), which its active neighbours see on their right-hand side. The arrays
/// coupling, on and lam have a zero entry before index 0 and after index m - 1 (padded).
ROV_TETHER_TARGET_CLONES void systemRows(const double* __restrict diag_active, const double* __restrict rhs_active,
                                         const double* __restrict coupling, const double* __restrict on,
                                         const double* __restrict lam, double* __restrict diag, double* __restrict off,
                                         double* __restrict rhs, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    const double a = on[k];
    const std::ptrdiff_t prev = static_cast<std::ptrdiff_t>(k) - 1;  // -1 at k = 0: the padding
    const double before = (1.0 - on[prev]) * coupling[prev] * lam[prev];
    const double after = (1.0 - on[k + 1]) * coupling[k] * lam[k + 1];
    diag[k] = a * diag_active[k] + (1.0 - a);
    rhs[k] = a * (rhs_active[k] + before + after) - (1.0 - a) * lam[k];
    off[k] = a * on[k + 1] * coupling[k];
  }
}

/// Checks the solution dlambda (d, padded like systemRows' arrays) against the active set and changes it
/// where they disagree: an active row whose multiplier would turn negative (it would push) leaves, an
/// inactive row whose segment the linearised step would stretch (the active row's residual at dlambda =
/// -lambda is positive) joins. Returns the number of changes.
ROV_TETHER_TARGET_CLONES std::size_t updateActiveSet(const double* __restrict diag_active,
                                                     const double* __restrict rhs_active,
                                                     const double* __restrict coupling, const double* __restrict alpha,
                                                     const double* __restrict lam, const double* __restrict d,
                                                     double* __restrict on, std::size_t m)
{
  double changes = 0.0;
  for (std::size_t k = 0; k < m; ++k)
  {
    const std::ptrdiff_t prev = static_cast<std::ptrdiff_t>(k) - 1;  // -1 at k = 0: the padding
    const double stretch = rhs_active[k] + diag_active[k] * lam[k] - coupling[prev] * d[prev] - coupling[k] * d[k + 1];
    const double a = on[k];
    const double push = lam[k] + d[k] < 0.0 ? 1.0 : 0.0;
    // (diag_active > alpha: not both ends pinned.)
    const double pull = ((diag_active[k] > alpha[k]) & (stretch > 0.0)) ? 1.0 : 0.0;
    const double change = a * push + (1.0 - a) * pull;
    on[k] = a + change - 2.0 * a * change;
    changes += change;
  }
  return static_cast<std::size_t>(changes);
}

/// The Newton step: dx_l = w_l (n_l dlambda_l - n_l-1 dlambda_l-1), and lambda += dlambda.
ROV_TETHER_TARGET_CLONES void applyDual(const double* __restrict w, const double* __restrict nx,
                                        const double* __restrict ny, const double* __restrict nz,
                                        const double* __restrict d, double* __restrict x, double* __restrict y,
                                        double* __restrict z, double* __restrict lam, std::size_t m)
{
  for (std::size_t l = 0; l <= m; ++l)
  {
    const double ahead = l < m ? d[l] : 0.0;
    const double behind = l > 0 ? d[l - 1] : 0.0;
    const double ax = l < m ? nx[l] : 0.0, ay = l < m ? ny[l] : 0.0, az = l < m ? nz[l] : 0.0;
    const double bx = l > 0 ? nx[l - 1] : 0.0, by = l > 0 ? ny[l - 1] : 0.0, bz = l > 0 ? nz[l - 1] : 0.0;
    const double free = w[l] > 0.0 ? 1.0 : 0.0;
    x[l] += free * w[l] * (ax * ahead - bx * behind);
    y[l] += free * w[l] * (ay * ahead - by * behind);
    z[l] += free * w[l] * (az * ahead - bz * behind);
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    lam[k] += d[k];
  }
}

/// applyDual with W_l = w_l I + dw_l t_l t_l^T.
ROV_TETHER_TARGET_CLONES void applyDualAnisotropic(const double* __restrict w, const double* __restrict dw,
                                                   const double* __restrict tx, const double* __restrict ty,
                                                   const double* __restrict tz, const double* __restrict nx,
                                                   const double* __restrict ny, const double* __restrict nz,
                                                   const double* __restrict d, double* __restrict x,
                                                   double* __restrict y, double* __restrict z, double* __restrict lam,
                                                   std::size_t m)
{
  for (std::size_t l = 0; l <= m; ++l)
  {
    const double ahead = l < m ? d[l] : 0.0;
    const double behind = l > 0 ? d[l - 1] : 0.0;
    const double vx = (l < m ? nx[l] : 0.0) * ahead - (l > 0 ? nx[l - 1] : 0.0) * behind;
    const double vy = (l < m ? ny[l] : 0.0) * ahead - (l > 0 ? ny[l - 1] : 0.0) * behind;
    const double vz = (l < m ? nz[l] : 0.0) * ahead - (l > 0 ? nz[l - 1] : 0.0) * behind;
    const double along = dw[l] * (vx * tx[l] + vy * ty[l] + vz * tz[l]);
    x[l] += w[l] * vx + along * tx[l];
    y[l] += w[l] * vy + along * ty[l];
    z[l] += w[l] * vz + along * tz[l];
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    lam[k] += d[k];
  }
}

}  // namespace

void DirectSolver::reserve(std::size_t n)
{
  if (nx_.size() >= n)
  {
    return;
  }
  for (auto* v : {&xt_,
                  &yt_,
                  &zt_,
                  &sx_,
                  &sy_,
                  &sz_,
                  &nx_,
                  &ny_,
                  &nz_,
                  &len_,
                  &c_,
                  &alpha_,
                  &diag_,
                  &off_,
                  &diag_active_,
                  &rhs_active_,
                  &gamma_,
                  &inv_rest_,
                  &saved_lambda_,
                  &extra_mobility_,
                  &response_,
                  &primal_lambda_,
                  &lambda_step_,
                  &warm_lambda_,
                  &correction_x_,
                  &correction_y_,
                  &correction_z_})
  {
    v->assign(n, 0.0);
  }
  // Padded by one zero on each side (systemRows, updateActiveSet).
  for (auto* v : {&dual_step_, &on_, &coupling_, &padded_lambda_, &zeros_})
  {
    v->assign(n + 2, 0.0);
  }
  for (auto* v : {&hessian_diag_, &hessian_first_, &hessian_second_})
  {
    v->assign(9 * n, 0.0);
  }
  taut_.assign(n, 0);
  step_.assign(3 * n, 0.0);
  grad_.assign(3 * n, 0.0);
  grad_step_.assign(3 * n, 0.0);
  work_.assign(36 * n, 0.0);
  band_.assign(9 * 3 * n, 0.0);  // LAPACK's band, up to half-bandwidth 8
}

void DirectSolver::project(Cable& cable, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  dual_iterations_ = primal_iterations_ = active_set_rounds_ = 0;
  residual_ = 0.0;
  if (n < f + 2)
  {
    tension_ratio_ = 0.0;
    return;
  }
  reserve(n);
  first_ = f;
  m_ = n - 1 - f;
  std::copy(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f), lambda.stretch.end(), warm_lambda_.begin() + f);
  std::fill(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f), lambda.stretch.end(), 0.0);
  std::fill(lambda.bend.begin() + static_cast<std::ptrdiff_t>(std::min(f, lambda.bend.size())), lambda.bend.end(), 0.0);
  bending_ = settings.bending && settings.bending_stiffness > 0.0 && m_ >= 2;
  unilateral_ = !bending_;
  nominal_ = cable.rest[n - 2];
  const double h2 = settings.time_step * settings.time_step;
  for (std::size_t k = 0; k < m_; ++k)
  {
    alpha_[k] = cable.rest[f + k] / (settings.axial_stiffness * h2);
    inv_rest_[k] = 1.0 / cable.rest[f + k];
  }
  for (std::size_t k = 0; bending_ && k + 1 < m_; ++k)
  {
    gamma_[k] = 0.5 * (cable.rest[f + k] + cable.rest[f + k + 1]) / (settings.bending_stiffness * h2);
  }
  std::copy(cable.x.begin() + static_cast<std::ptrdiff_t>(f), cable.x.end(), xt_.begin());
  std::copy(cable.y.begin() + static_cast<std::ptrdiff_t>(f), cable.y.end(), yt_.begin());
  std::copy(cable.z.begin() + static_cast<std::ptrdiff_t>(f), cable.z.end(), zt_.begin());
  geometry(cable);

  double* lam = lambda.stretch.data() + f;
  const double tolerance = settings.tolerance;
  drum_ = settings.drum;
  if (drum_ != nullptr)
  {
    drum_->prepare(alpha_[0]);
    if (bending_)
    {
      // The spool segment lengthens by the drum's pay-out within the solve, which its rest length does not
      // know: the joint's curvature a x_0 - (a + b) x_1 + b x_2 would read that as a kink and pull along the
      // cable (2 N at 1 m/s with EI 0.2). The cable leaves the spool over a sheave: a hinge there.
      gamma_[0] = std::numeric_limits<double>::infinity();
    }
  }
  bool primal = bending_ || tension_ratio_ > kDualTensionRatio;
  warmStart(cable, lam, primal);
  if (!primal)
  {
    residual_ = dualResidual(cable, lam);
    // The first active set also holds the segments taut at the end of the last step (the set changes little
    // from step to step); a wrong guess costs a round, not the answer.
    for (std::size_t k = 0; k < m_; ++k)
    {
      on()[k] = taut_[f + k] && cable.stretch_weight[f + k] > 0.0 ? 1.0 : on()[k];
    }
    while (residual_ > tolerance && dual_iterations_ < std::min(settings.iterations, kMaxDualIterations))
    {
      save(cable);
      std::copy(lam, lam + m_, saved_lambda_.begin());
      dualStep(cable, lam);
      ++dual_iterations_;
      geometry(cable);
      const double r = dualResidual(cable, lam);
      if (!(r < residual_))
      {
        // No progress (a tensioned chain's transverse motion, or a snap): undo, and solve on the primal path.
        restore(cable);
        std::copy(saved_lambda_.begin(), saved_lambda_.begin() + static_cast<std::ptrdiff_t>(m_), lam);
        geometry(cable);
        break;
      }
      residual_ = r;
    }
    primal = residual_ > tolerance && dual_iterations_ < settings.iterations;
  }
  if (primal)
  {
    // The multipliers' first estimate: the dual's, or the warm start's.
    std::copy(lam, lam + m_, primal_lambda_.begin());
    residual_ = std::numeric_limits<double>::infinity();
    while (residual_ > tolerance && lastIterations() < settings.iterations)
    {
      if (!std::isfinite(primalStep(cable)))
      {
        break;  // the system was not definite: leave the step as it is (reported through the residual)
      }
      ++primal_iterations_;
      residual_ = primalResidual(cable);
    }
    for (std::size_t k = 0; k < m_; ++k)
    {
      lam[k] = unilateral_ ? std::max(primal_lambda_[k], 0.0) : primal_lambda_[k];
    }
  }
  if (drum_ != nullptr)
  {
    if (cable.inv_mass[f] + cable.inv_mass[f + 1] == 0.0)
    {
      lam[0] = drum_->force(c_[0]);  // a segment nothing can move: the law alone
    }
    drum_->payout = drum_->payoutAt(c_[0]);
  }
  // What the next step starts from: the correction this step made, the segments taut now, and how hard the
  // chain is pulled.
  for (std::size_t l = 0; l <= m_; ++l)
  {
    correction_x_[f + l] = cable.x[f + l] - xt_[l];
    correction_y_[f + l] = cable.y[f + l] - yt_[l];
    correction_z_[f + l] = cable.z[f + l] - zt_[l];
  }
  std::fill(taut_.begin(), taut_.end(), 0);
  tension_ratio_ = 0.0;
  for (std::size_t k = 0; k < m_; ++k)
  {
    // A slack cable segment carries nothing, exactly (its multiplier can end a rounding below 0).
    lam[k] = unilateral_ ? std::max(lam[k], 0.0) : lam[k];
    taut_[f + k] = lam[k] > 0.0 ? 1 : 0;
    const double weight = cable.stretch_weight[f + k];
    if (weight > 0.0 && len_[k] > 0.0)
    {
      tension_ratio_ = std::max(tension_ratio_, lam[k] / (weight * len_[k]));
    }
  }
}

void DirectSolver::warmStart(Cable& cable, double* lambda, bool primal)
{
  // A chain whose tension changes little from step to step (a hanging or towed tether) starts next to its
  // solution, and Newton has little left to do: lambda = the last step's multipliers, and the positions
  // x~ + W J^T lambda (dual path), or x~ plus the last step's correction x - x~ (primal path, where the
  // tension ratio makes W J^T lambda, each pull larger than a segment, too sensitive to where J is taken).
  const std::size_t f = first_;
  const std::size_t m = m_;
  const double* w = cable.inv_mass.data() + f;
  if (primal)
  {
    std::copy(warm_lambda_.begin() + static_cast<std::ptrdiff_t>(f),
              warm_lambda_.begin() + static_cast<std::ptrdiff_t>(f + m), lambda);
    for (std::size_t l = 0; l <= m; ++l)
    {
      const double free = w[l] > 0.0 ? 1.0 : 0.0;
      cable.x[f + l] += free * correction_x_[f + l];
      cable.y[f + l] += free * correction_y_[f + l];
      cable.z[f + l] += free * correction_z_[f + l];
    }
    geometry(cable);
    return;
  }
  std::copy(warm_lambda_.begin() + static_cast<std::ptrdiff_t>(f),
            warm_lambda_.begin() + static_cast<std::ptrdiff_t>(f + m), step());
  step()[m] = 0.0;
  if (cable.anisotropic)
  {
    for (std::size_t l = 0; l <= m; ++l)
    {
      extra_mobility_[l] = cable.inv_mass_along[f + l] - w[l];
    }
    applyDualAnisotropic(w, extra_mobility_.data(), cable.tx.data() + f, cable.ty.data() + f, cable.tz.data() + f,
                         nx_.data(), ny_.data(), nz_.data(), step(), cable.x.data() + f, cable.y.data() + f,
                         cable.z.data() + f, lambda, m);
  }
  else
  {
    applyDual(w, nx_.data(), ny_.data(), nz_.data(), step(), cable.x.data() + f, cable.y.data() + f, cable.z.data() + f,
              lambda, m);
  }
  geometry(cable);
}

void DirectSolver::forget()
{
  std::fill(taut_.begin(), taut_.end(), 0);
  for (auto* v : {&correction_x_, &correction_y_, &correction_z_})
  {
    std::fill(v->begin(), v->end(), 0.0);
  }
  tension_ratio_ = 0.0;
}

void DirectSolver::geometry(const Cable& cable)
{
  const std::size_t f = first_;
  segmentGeometry(cable.x.data() + f, cable.y.data() + f, cable.z.data() + f, cable.rest.data() + f, nx_.data(),
                  ny_.data(), nz_.data(), len_.data(), c_.data(), m_);
}

double DirectSolver::dualResidual(const Cable& cable, const double* lambda)
{
  if (drum_ == nullptr)
  {
    return activeSet(cable.inv_mass.data() + first_, inv_rest_.data(), c_.data(), alpha_.data(), lambda, on(), m_);
  }
  // The spool segment follows the drum's law, not C = alpha lambda (it lengthens by the pay-out): its
  // residual is the force it carries against the law's, as a displacement. The others are as without a drum.
  const double worst = activeSet(cable.inv_mass.data() + first_ + 1, inv_rest_.data() + 1, c_.data() + 1,
                                 alpha_.data() + 1, lambda + 1, on() + 1, m_ - 1);
  const double mobility = cable.inv_mass[first_] + cable.inv_mass[first_ + 1];
  return std::max(worst, std::abs(lambda[0] - drum_->force(c_[0])) * mobility * inv_rest_[0]);
}

bool DirectSolver::solveRows()
{
  systemRows(diag_active_.data(), rhs_active_.data(), coupling(), on(), padded_lambda(), diag_.data(), off_.data(),
             step(), m_);
  return linear_ == LinearSolve::kLapack ? banded::solveTridiagonalLapack(diag_.data(), off_.data(), step(), m_)
                                         : banded::solveTridiagonalSweep(diag_.data(), off_.data(), step(), m_);
}

bool DirectSolver::solveWithDrum(const double* lambda)
{
  // Row 0, the spool segment, follows the drum's law (monotone, piecewise linear): the rest of the chain
  // answers its multiplier linearly, dlambda = p + q dlambda_0, so its linearised stretch is
  // c_0 - mobility dlambda_0 - coupling_0 (p_1 + q_1 dlambda_0) = a - b lambda_0, and the law is met
  // exactly at lambda_0 = drum.forceAgainst(a, b). Two solves: p with dlambda_0 = 0, q for a unit one.
  const std::size_t m = m_;
  const double mobility = diag_active_[0] - alpha_[0];  // n . (W_0 + W_1) n
  const double lambda0 = lambda[0];
  on()[0] = 0.0;
  padded_lambda()[0] = 0.0;  // an inactive row 0 with dlambda_0 = -0
  if (!solveRows())
  {
    return false;
  }
  std::copy(step(), step() + m, response_.begin());  // p
  if (m > 1)
  {
    // q: row 0 fixed at 1, its coupling on row 1's right-hand side, nothing else driving.
    systemRows(diag_active_.data(), zeros_.data(), coupling(), on(), zeros_.data() + 1, diag_.data(), off_.data(),
               step(), m);
    step()[0] = 1.0;
    step()[1] = on()[1] > 0.0 ? -coupling()[0] : 0.0;
    const bool ok = linear_ == LinearSolve::kLapack
                        ? banded::solveTridiagonalLapack(diag_.data(), off_.data(), step(), m)
                        : banded::solveTridiagonalSweep(diag_.data(), off_.data(), step(), m);
    if (!ok)
    {
      return false;
    }
  }
  const double p1 = m > 1 ? response_[1] : 0.0;
  const double q1 = m > 1 ? step()[1] : 0.0;
  const double a = c_[0] - coupling()[0] * p1 + (mobility + coupling()[0] * q1) * lambda0;
  const double b = mobility + coupling()[0] * q1;
  const double d0 = drum_->forceAgainst(a, b) - lambda0;
  for (std::size_t k = 1; k < m; ++k)
  {
    step()[k] = response_[k] + step()[k] * d0;
  }
  step()[0] = d0;
  return true;
}

void DirectSolver::dualStep(Cable& cable, double* lambda)
{
  const std::size_t f = first_;
  const std::size_t m = m_;
  const double* w = cable.inv_mass.data() + f;
  if (cable.anisotropic)
  {
    for (std::size_t l = 0; l <= m; ++l)
    {
      extra_mobility_[l] = cable.inv_mass_along[f + l] - w[l];
    }
    activeRowsAnisotropic(w, extra_mobility_.data(), cable.tx.data() + f, cable.ty.data() + f, cable.tz.data() + f,
                          alpha_.data(), c_.data(), lambda, nx_.data(), ny_.data(), nz_.data(), diag_active_.data(),
                          rhs_active_.data(), coupling(), m);
  }
  else
  {
    activeRows(w, alpha_.data(), c_.data(), lambda, nx_.data(), ny_.data(), nz_.data(), diag_active_.data(),
               rhs_active_.data(), coupling(), m);
  }
  // The padded copies: a zero before the first row and after the last.
  std::copy(lambda, lambda + m, padded_lambda());
  padded_lambda()[m] = on()[m] = step()[m] = 0.0;
  // The linearised problem is a complementarity problem (a segment pulls, or it is not stretched). It is
  // solved by primal-dual active sets on the same linearisation, so the outer Newton iterations see only the
  // nonlinearity: solve with the active set, let go of rows that would push, take in rows that would be
  // stretched, until the set holds.
  for (int round = 0; round < kMaxActiveSetRounds; ++round)
  {
    if (!(drum_ != nullptr ? solveWithDrum(lambda) : solveRows()))
    {
      std::fill(step(), step() + m, 0.0);
      break;
    }
    ++active_set_rounds_;
    // With the drum, row 0 follows its law exactly (solveWithDrum); the active set is that of rows 1...
    const std::size_t skip = drum_ != nullptr ? 1 : 0;
    if (m <= skip || updateActiveSet(diag_active_.data() + skip, rhs_active_.data() + skip, coupling() + skip,
                                     alpha_.data() + skip, lambda + skip, step() + skip, on() + skip, m - skip) == 0)
    {
      break;
    }
  }
  if (cable.anisotropic)
  {
    applyDualAnisotropic(w, extra_mobility_.data(), cable.tx.data() + f, cable.ty.data() + f, cable.tz.data() + f,
                         nx_.data(), ny_.data(), nz_.data(), step(), cable.x.data() + f, cable.y.data() + f,
                         cable.z.data() + f, lambda, m);
    return;
  }
  applyDual(w, nx_.data(), ny_.data(), nz_.data(), step(), cable.x.data() + f, cable.y.data() + f, cable.z.data() + f,
            lambda, m);
}

void DirectSolver::save(const Cable& cable)
{
  const auto f = static_cast<std::ptrdiff_t>(first_);
  std::copy(cable.x.begin() + f, cable.x.end(), sx_.begin());
  std::copy(cable.y.begin() + f, cable.y.end(), sy_.begin());
  std::copy(cable.z.begin() + f, cable.z.end(), sz_.begin());
}

void DirectSolver::restore(Cable& cable) const
{
  const auto f = static_cast<std::ptrdiff_t>(first_);
  const auto count = static_cast<std::ptrdiff_t>(m_ + 1);
  std::copy(sx_.begin(), sx_.begin() + count, cable.x.begin() + f);
  std::copy(sy_.begin(), sy_.begin() + count, cable.y.begin() + f);
  std::copy(sz_.begin(), sz_.begin() + count, cable.z.begin() + f);
}

}  // namespace rov_tether
