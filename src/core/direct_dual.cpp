// The direct solver's dual path (direct_dual.hpp): Newton on the multipliers with an exact tridiagonal
// solve per active set. See direct_solver.hpp.
#include "direct_dual.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "banded.hpp"
#include "simd.hpp"

namespace rov_tether
{
namespace
{

/// Rounds of active-set changes on one linearisation.
constexpr int kMaxActiveSetRounds = 30;

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

void DualNewton::reserve(std::size_t n)
{
  if (diag_.size() >= n)
  {
    return;
  }
  for (auto* v : {&diag_, &off_, &diag_active_, &rhs_active_, &saved_lambda_, &extra_mobility_, &response_})
  {
    v->assign(n, 0.0);
  }
  // Padded by one zero on each side (systemRows, updateActiveSet).
  for (auto* v : {&dual_step_, &coupling_, &padded_lambda_, &zeros_})
  {
    v->assign(n + 2, 0.0);
  }
}

void DualNewton::warmStart(Cable& cable, double* lambda)
{
  // A chain whose tension changes little from step to step (a hanging or towed tether) starts next to its
  // solution, and Newton has little left to do: lambda = the last step's multipliers, and the positions
  // x~ + W J^T lambda.
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  std::copy(ws_.warm_lambda.begin() + static_cast<std::ptrdiff_t>(f),
            ws_.warm_lambda.begin() + static_cast<std::ptrdiff_t>(f + m), dlambda());
  dlambda()[m] = 0.0;
  if (cable.anisotropic)
  {
    anisotropicMobility(cable);
  }
  apply(cable, lambda);
  ws_.geometry(cable);
}

DualNewton::Result DualNewton::solve(Cable& cable, double* lambda, double tolerance, int max_iterations)
{
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  Result result;
  result.residual = residual(cable, lambda);
  // The first active set also holds the segments taut at the end of the last step (the set changes little
  // from step to step); a wrong guess costs a round, not the answer.
  double* on = ws_.on();
  for (std::size_t k = 0; k < m; ++k)
  {
    on[k] = ws_.taut[f + k] && cable.stretch_weight[f + k] > 0.0 ? 1.0 : on[k];
  }
  while (result.residual > tolerance && result.iterations < max_iterations)
  {
    ws_.save(cable);
    std::copy(lambda, lambda + m, saved_lambda_.begin());
    step(cable, lambda, &result.rounds);
    ++result.iterations;
    ws_.geometry(cable);
    const double r = residual(cable, lambda);
    if (!(r < result.residual))
    {
      // No progress (a tensioned chain's transverse motion, or a snap): undo, and solve on the primal path.
      ws_.restore(cable);
      std::copy(saved_lambda_.begin(), saved_lambda_.begin() + static_cast<std::ptrdiff_t>(m), lambda);
      ws_.geometry(cable);
      break;
    }
    result.residual = r;
  }
  return result;
}

double DualNewton::residual(const Cable& cable, const double* lambda)
{
  const std::size_t f = ws_.first;
  if (ws_.drum == nullptr)
  {
    return activeSet(cable.inv_mass.data() + f, ws_.inv_rest.data(), ws_.c.data(), ws_.alpha.data(), lambda, ws_.on(),
                     ws_.m);
  }
  // The spool segment follows the drum's law, not C = alpha lambda (it lengthens by the pay-out): its residual is
  // DirectWorkspace::drumResidual. The others are as without a drum.
  const double worst = activeSet(cable.inv_mass.data() + f + 1, ws_.inv_rest.data() + 1, ws_.c.data() + 1,
                                 ws_.alpha.data() + 1, lambda + 1, ws_.on() + 1, ws_.m - 1);
  return std::max(worst, ws_.drumResidual(lambda[0], cable.inv_mass[f] + cable.inv_mass[f + 1]));
}

bool DualNewton::solveRows()
{
  systemRows(diag_active_.data(), rhs_active_.data(), coupling(), ws_.on(), paddedLambda(), diag_.data(), off_.data(),
             dlambda(), ws_.m);
  return linear_ == DirectSolver::LinearSolve::kLapack
             ? banded::solveTridiagonalLapack(diag_.data(), off_.data(), dlambda(), ws_.m)
             : banded::solveTridiagonalSweep(diag_.data(), off_.data(), dlambda(), ws_.m);
}

bool DualNewton::solveWithDrum(const double* lambda)
{
  // Row 0, the spool segment, follows the drum's law (monotone, piecewise linear): the rest of the chain
  // answers its multiplier linearly, dlambda = p + q dlambda_0, so its linearised stretch is
  // c_0 - mobility dlambda_0 - coupling_0 (p_1 + q_1 dlambda_0) = a - b lambda_0, and the law is met
  // exactly at lambda_0 = drum.forceAgainst(a, b). Two solves: p with dlambda_0 = 0, q for a unit one.
  const std::size_t m = ws_.m;
  double* on = ws_.on();
  double* d = dlambda();
  const double mobility = diag_active_[0] - ws_.alpha[0];  // n . (W_0 + W_1) n
  const double lambda0 = lambda[0];
  on[0] = 0.0;
  paddedLambda()[0] = 0.0;  // an inactive row 0 with dlambda_0 = -0
  if (!solveRows())
  {
    return false;
  }
  std::copy(d, d + m, response_.begin());  // p
  if (m > 1)
  {
    // q: row 0 fixed at 1, its coupling on row 1's right-hand side, nothing else driving.
    systemRows(diag_active_.data(), zeros_.data(), coupling(), on, zeros_.data() + 1, diag_.data(), off_.data(), d, m);
    d[0] = 1.0;
    d[1] = on[1] > 0.0 ? -coupling()[0] : 0.0;
    const bool ok = linear_ == DirectSolver::LinearSolve::kLapack
                        ? banded::solveTridiagonalLapack(diag_.data(), off_.data(), d, m)
                        : banded::solveTridiagonalSweep(diag_.data(), off_.data(), d, m);
    if (!ok)
    {
      return false;
    }
  }
  const double p1 = m > 1 ? response_[1] : 0.0;
  const double q1 = m > 1 ? d[1] : 0.0;
  const double a = ws_.c[0] - coupling()[0] * p1 + (mobility + coupling()[0] * q1) * lambda0;
  const double b = mobility + coupling()[0] * q1;
  const double d0 = ws_.drum->forceAgainst(a, b) - lambda0;
  for (std::size_t k = 1; k < m; ++k)
  {
    d[k] = response_[k] + d[k] * d0;
  }
  d[0] = d0;
  return true;
}

void DualNewton::anisotropicMobility(const Cable& cable)
{
  const std::size_t f = ws_.first;
  for (std::size_t l = 0; l <= ws_.m; ++l)
  {
    extra_mobility_[l] = cable.inv_mass_along[f + l] - cable.inv_mass[f + l];
  }
}

void DualNewton::step(Cable& cable, double* lambda, int* rounds)
{
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  const double* w = cable.inv_mass.data() + f;
  double* on = ws_.on();
  if (cable.anisotropic)
  {
    anisotropicMobility(cable);
    activeRowsAnisotropic(w, extra_mobility_.data(), cable.tx.data() + f, cable.ty.data() + f, cable.tz.data() + f,
                          ws_.alpha.data(), ws_.c.data(), lambda, ws_.nx.data(), ws_.ny.data(), ws_.nz.data(),
                          diag_active_.data(), rhs_active_.data(), coupling(), m);
  }
  else
  {
    activeRows(w, ws_.alpha.data(), ws_.c.data(), lambda, ws_.nx.data(), ws_.ny.data(), ws_.nz.data(),
               diag_active_.data(), rhs_active_.data(), coupling(), m);
  }
  // The padded copies: a zero before the first row and after the last.
  std::copy(lambda, lambda + m, paddedLambda());
  paddedLambda()[m] = on[m] = dlambda()[m] = 0.0;
  // The linearised problem is a complementarity problem (a segment pulls, or it is not stretched). It is
  // solved by primal-dual active sets on the same linearisation, so the outer Newton iterations see only the
  // nonlinearity: solve with the active set, let go of rows that would push, take in rows that would be
  // stretched, until the set holds.
  for (int round = 0; round < kMaxActiveSetRounds; ++round)
  {
    if (!(ws_.drum != nullptr ? solveWithDrum(lambda) : solveRows()))
    {
      std::fill(dlambda(), dlambda() + m, 0.0);
      break;
    }
    ++*rounds;
    // With the drum, row 0 follows its law exactly (solveWithDrum); the active set is that of rows 1...
    const std::size_t skip = ws_.drum != nullptr ? 1 : 0;
    if (m <= skip ||
        updateActiveSet(diag_active_.data() + skip, rhs_active_.data() + skip, coupling() + skip,
                        ws_.alpha.data() + skip, lambda + skip, dlambda() + skip, on + skip, m - skip) == 0)
    {
      break;
    }
  }
  apply(cable, lambda);
}

void DualNewton::apply(Cable& cable, double* lambda)
{
  const std::size_t f = ws_.first;
  const double* w = cable.inv_mass.data() + f;
  if (cable.anisotropic)
  {
    applyDualAnisotropic(w, extra_mobility_.data(), cable.tx.data() + f, cable.ty.data() + f, cable.tz.data() + f,
                         ws_.nx.data(), ws_.ny.data(), ws_.nz.data(), dlambda(), cable.x.data() + f, cable.y.data() + f,
                         cable.z.data() + f, lambda, ws_.m);
    return;
  }
  applyDual(w, ws_.nx.data(), ws_.ny.data(), ws_.nz.data(), dlambda(), cable.x.data() + f, cable.y.data() + f,
            cable.z.data() + f, lambda, ws_.m);
}

}  // namespace rov_tether
