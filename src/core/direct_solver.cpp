#include "rov_tether/direct_solver.hpp"

#include <algorithm>
#include <cmath>

#include "rov_tether/banded.hpp"
#include "rov_tether/simd.hpp"

namespace rov_tether
{
namespace
{

/// Halvings of a Newton step that does not lower the residual (the last is taken whatever it gives).
constexpr int kMaxHalvings = 4;
/// Below this largest relative residual every Newton step is taken whole: the linearisation is good
/// there, and Newton converges quadratically.
constexpr double kGlobalResidual = 1e-3;
/// A diagonal this small belongs to a row no free particle takes part in: solved as the identity.
constexpr double kTinyDiagonal = 1e-300;

/// One row's gradient at one particle: a stretch row (vector n times sign) or a bending row a (c e_a).
struct Gradient
{
  std::size_t row;
  bool stretch;
  double sign_or_coefficient;  ///< Stretch: +1 or -1 times n; bending: c.
  std::size_t segment;         ///< Stretch: its segment k (for n); bending: unused.
  int axis;                    ///< Bending: 0, 1, 2.
};

/// Unit vector n_k and value C_k = |d_k| - L_k of each of m segments (particles 0..m of the arrays).
ROV_TETHER_TARGET_CLONES void segmentGeometry(const double* __restrict x, const double* __restrict y,
                                              const double* __restrict z, const double* __restrict rest,
                                              double* __restrict nx, double* __restrict ny, double* __restrict nz,
                                              double* __restrict c, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    const double dx = x[k + 1] - x[k];
    const double dy = y[k + 1] - y[k];
    const double dz = z[k + 1] - z[k];
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double inv = 1.0 / (length + 1e-300);  // a zero-length segment has n = 0
    nx[k] = dx * inv, ny[k] = dy * inv, nz[k] = dz * inv;
    c[k] = length - rest[k];
  }
}

/// The tridiagonal system of the active stretch constraints (on[k] 1 or 0): (w_k + w_k+1 + alpha_k) on
/// the diagonal and -w_k+1 n_k . n_k+1 beside it, right-hand side C_k - alpha_k lambda_k; an inactive row
/// is the identity with dlambda = -lambda (it carries nothing).
ROV_TETHER_TARGET_CLONES void assembleTridiagonal(const double* __restrict w, const double* __restrict alpha,
                                                  const double* __restrict c, const double* __restrict lam,
                                                  const double* __restrict nx, const double* __restrict ny,
                                                  const double* __restrict nz, const double* __restrict on,
                                                  double* __restrict diag, double* __restrict off,
                                                  double* __restrict rhs, std::size_t m)
{
  for (std::size_t k = 0; k < m; ++k)
  {
    const double a = on[k];
    diag[k] = a * (w[k] + w[k + 1] + alpha[k]) + (1.0 - a);
    rhs[k] = a * (c[k] - alpha[k] * lam[k]) - (1.0 - a) * lam[k];
  }
  for (std::size_t k = 0; k + 1 < m; ++k)
  {
    off[k] = -on[k] * on[k + 1] * w[k + 1] * (nx[k] * nx[k + 1] + ny[k] * ny[k + 1] + nz[k] * nz[k + 1]);
  }
}

/// dx = -M^-1 J^T dlambda for the stretch rows (dlambda_k = d[k stride]): segment k pulls particle k along
/// +n_k and particle k+1 along -n_k. Written per particle (a gather), so iterations are independent.
ROV_TETHER_TARGET_CLONES void applyStretch(const double* __restrict w, const double* __restrict nx,
                                           const double* __restrict ny, const double* __restrict nz,
                                           const double* __restrict d, std::size_t stride, double* __restrict x,
                                           double* __restrict y, double* __restrict z, double* __restrict lam,
                                           std::size_t m)
{
  x[0] += w[0] * nx[0] * d[0], y[0] += w[0] * ny[0] * d[0], z[0] += w[0] * nz[0] * d[0];
  for (std::size_t l = 1; l < m; ++l)
  {
    const double ahead = d[l * stride];
    const double behind = d[(l - 1) * stride];
    x[l] += w[l] * (nx[l] * ahead - nx[l - 1] * behind);
    y[l] += w[l] * (ny[l] * ahead - ny[l - 1] * behind);
    z[l] += w[l] * (nz[l] * ahead - nz[l - 1] * behind);
  }
  const double last = d[(m - 1) * stride];
  x[m] -= w[m] * nx[m - 1] * last, y[m] -= w[m] * ny[m - 1] * last, z[m] -= w[m] * nz[m - 1] * last;
  for (std::size_t k = 0; k < m; ++k)
  {
    lam[k] += d[k * stride];
  }
}

/// The active set (on[k] = 1 or 0) and the largest relative residual of the active stretch constraints:
/// a segment takes part when a free particle can move it and it carries tension or is not shorter than
/// its rest length beyond the tolerance, or always when `bilateral`.
ROV_TETHER_TARGET_CLONES double activeSet(const double* __restrict weight, const double* __restrict lam,
                                          const double* __restrict c, const double* __restrict alpha,
                                          const double* __restrict rest, double tolerance, bool bilateral,
                                          double* __restrict on, std::size_t m)
{
  double worst = 0.0;
  for (std::size_t k = 0; k < m; ++k)
  {
    const bool active = weight[k] > 0.0 && (bilateral || lam[k] > 0.0 || c[k] >= -tolerance * rest[k]);
    on[k] = active ? 1.0 : 0.0;
    const double r = std::abs(c[k] - alpha[k] * lam[k]) / rest[k];
    worst = std::max(worst, active ? r : 0.0);
  }
  return worst;
}

}  // namespace

void DirectSolver::project(Cable& cable, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  iterations_ = 0;
  residual_ = 0.0;
  if (n < f + 2)
  {
    return;
  }
  const std::size_t m = n - 1 - f;  // deployed segments
  std::fill(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f), lambda.stretch.end(), 0.0);
  std::fill(lambda.bend.begin() + static_cast<std::ptrdiff_t>(std::min(f, lambda.bend.size())), lambda.bend.end(), 0.0);
  if (nx_.size() < n)
  {
    // Sized for the whole cable once: pay-out never allocates.
    for (auto* v : {&nx_, &ny_, &nz_, &stretch_c_, &stretch_alpha_, &bend_alpha_, &diag_, &off_, &on_, &saved_x_,
                    &saved_y_, &saved_z_, &saved_lambda_})
    {
      v->assign(n, 0.0);
    }
    bend_c_.assign(3 * n, 0.0);
    bend_lambda_.assign(3 * n, 0.0);
    saved_bend_.assign(3 * n, 0.0);
    rhs_.assign(4 * n, 0.0);
    band_.assign(static_cast<std::size_t>(kBand + 1) * 4 * n, 0.0);
  }
  const bool bending = settings.bending && settings.bending_stiffness > 0.0 && m >= 2;
  const double h2 = settings.time_step * settings.time_step;
  stretch_compliance_ = 1.0 / (settings.axial_stiffness * h2);
  bend_compliance_ = bending ? 1.0 / (settings.bending_stiffness * h2) : 0.0;
  for (std::size_t k = 0; k < m; ++k)
  {
    stretch_alpha_[k] = cable.rest[f + k] * stretch_compliance_;
  }
  if (bending)
  {
    for (std::size_t k = 0; k + 1 < m; ++k)
    {
      bend_alpha_[k] = 0.5 * (cable.rest[f + k] + cable.rest[f + k + 1]) * bend_compliance_;
    }
    std::fill(bend_lambda_.begin(), bend_lambda_.begin() + static_cast<std::ptrdiff_t>(3 * m), 0.0);
  }
  residual_ = residuals(cable, lambda, bending, settings.tolerance);
  while (residual_ > settings.tolerance && iterations_ < settings.iterations)
  {
    newtonStep(cable, lambda, bending);
    // Backtracking: a full step is taken when it lowers the largest residual (near the solution it
    // always does, and Newton converges quadratically); far from it, where the linearisation misleads
    // (a nearly straight chain pulled taut, whose straightening has no first-order effect on its
    // length), the step is halved until it does.
    save(cable, lambda, bending);
    for (int halving = 0;; ++halving)
    {
      applyStep(cable, lambda, bending);
      const double r = residuals(cable, lambda, bending, settings.tolerance);
      if (r < residual_ || residual_ < kGlobalResidual || halving == kMaxHalvings)
      {
        residual_ = r;
        break;
      }
      restore(cable, lambda, bending);
      residuals(cable, lambda, bending, settings.tolerance);  // the linearisation the step was made at
      std::transform(rhs_.begin(), rhs_.end(), rhs_.begin(), [](double d) { return 0.5 * d; });
    }
    ++iterations_;
  }
}

double DirectSolver::residuals(const Cable& cable, const Multipliers& lambda, bool bending, double tolerance)
{
  const std::size_t f = cable.first;
  const std::size_t m = cable.size() - 1 - f;
  segmentGeometry(cable.x.data() + f, cable.y.data() + f, cable.z.data() + f, cable.rest.data() + f, nx_.data(),
                  ny_.data(), nz_.data(), stretch_c_.data(), m);
  // A segment between two pinned particles cannot be corrected. A segment shorter than its rest length
  // (beyond the tolerance) that carries nothing is slack; one at its length or longer takes part, and the
  // solve decides whether it pulls (a push drops it, see newtonStep). Segments that carried tension at
  // the end of the last step start active too: the set changes little from step to step.
  // With bending stiffness the cable is a rod: it carries compression (and buckles through its
  // bending), so its stretch constraints are two-sided. Without, a segment shorter than its rest length
  // would let the bending constraints be met by shrinking instead of bending.
  double worst = activeSet(cable.stretch_weight.data() + f, lambda.stretch.data() + f, stretch_c_.data(),
                           stretch_alpha_.data(), cable.rest.data() + f, tolerance, bending, on_.data(), m);
  if (bending)
  {
    for (std::size_t k = 0; k + 1 < m; ++k)
    {
      const std::size_t j = f + k;
      const double a = 1.0 / cable.rest[j];
      const double b = 1.0 / cable.rest[j + 1];
      const double* coordinates[3] = {cable.x.data(), cable.y.data(), cable.z.data()};
      double norm2 = 0.0;
      for (int axis = 0; axis < 3; ++axis)
      {
        const double* p = coordinates[axis];
        const double c = (p[j + 2] - p[j + 1]) * b - (p[j + 1] - p[j]) * a;
        bend_c_[3 * k + axis] = c;
        const double r = c - bend_alpha_[k] * bend_lambda_[3 * k + axis];
        norm2 += r * r;
      }
      worst = std::max(worst, std::sqrt(norm2));
    }
  }
  return worst;
}

void DirectSolver::newtonStep(Cable& cable, Multipliers& lambda, bool bending)
{
  const std::size_t f = cable.first;
  const std::size_t m = cable.size() - 1 - f;
  const double* w = cable.inv_mass.data() + f;  // w[l], l = 0..m: deployed particle l
  const std::size_t rows = bending ? 4 * m - 3 : m;
  if (bending)
  {
    assembleBanded(cable, lambda, m);
    solveBanded(rows);
  }
  else
  {
    assembleTridiagonal(w, stretch_alpha_.data(), stretch_c_.data(), lambda.stretch.data() + f, nx_.data(), ny_.data(),
                        nz_.data(), on_.data(), diag_.data(), off_.data(), rhs_.data(), m);
    solveTridiagonal(rows);
  }
  // Without bending stiffness, a segment whose multiplier would turn negative would push, which a cable
  // cannot: it goes slack (lambda 0). The next iteration's residuals show what that changed.
  for (std::size_t k = 0; !bending && k < m; ++k)
  {
    rhs_[k] = std::max(rhs_[k], -lambda.stretch[f + k]);
  }
}

void DirectSolver::applyStep(Cable& cable, Multipliers& lambda, bool bending)
{
  const std::size_t f = cable.first;
  const std::size_t m = cable.size() - 1 - f;
  const double* w = cable.inv_mass.data() + f;
  applyStretch(w, nx_.data(), ny_.data(), nz_.data(), rhs_.data(), bending ? 4 : 1, cable.x.data() + f,
               cable.y.data() + f, cable.z.data() + f, lambda.stretch.data() + f, m);
  if (bending)
  {
    double* coordinates[3] = {cable.x.data(), cable.y.data(), cable.z.data()};
    for (std::size_t k = 0; k + 1 < m; ++k)
    {
      const std::size_t j = f + k;
      const double a = 1.0 / cable.rest[j];
      const double b = 1.0 / cable.rest[j + 1];
      for (int axis = 0; axis < 3; ++axis)
      {
        const double d = rhs_[4 * k + 1 + static_cast<std::size_t>(axis)];
        bend_lambda_[3 * k + axis] += d;
        double* p = coordinates[axis];
        // Gradient of C_b: +a at x_j, -(a + b) at x_j+1, +b at x_j+2.
        p[j] -= w[k] * a * d;
        p[j + 1] += w[k + 1] * (a + b) * d;
        p[j + 2] -= w[k + 2] * b * d;
      }
    }
  }
}

void DirectSolver::save(const Cable& cable, const Multipliers& lambda, bool bending)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  std::copy(cable.x.begin() + f, cable.x.end(), saved_x_.begin());
  std::copy(cable.y.begin() + f, cable.y.end(), saved_y_.begin());
  std::copy(cable.z.begin() + f, cable.z.end(), saved_z_.begin());
  std::copy(lambda.stretch.begin() + f, lambda.stretch.end(), saved_lambda_.begin());
  if (bending)
  {
    std::copy(bend_lambda_.begin(), bend_lambda_.begin() + static_cast<std::ptrdiff_t>(3 * (n - 1 - f)),
              saved_bend_.begin());
  }
}

void DirectSolver::restore(Cable& cable, Multipliers& lambda, bool bending)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  const auto count = static_cast<std::ptrdiff_t>(n - f);
  std::copy(saved_x_.begin(), saved_x_.begin() + count, cable.x.begin() + static_cast<std::ptrdiff_t>(f));
  std::copy(saved_y_.begin(), saved_y_.begin() + count, cable.y.begin() + static_cast<std::ptrdiff_t>(f));
  std::copy(saved_z_.begin(), saved_z_.begin() + count, cable.z.begin() + static_cast<std::ptrdiff_t>(f));
  std::copy(saved_lambda_.begin(), saved_lambda_.begin() + count - 1,
            lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f));
  if (bending)
  {
    std::copy(saved_bend_.begin(), saved_bend_.begin() + 3 * (count - 1), bend_lambda_.begin());
  }
}

void DirectSolver::assembleBanded(const Cable& cable, const Multipliers& lambda, std::size_t m)
{
  const std::size_t f = cable.first;
  const std::size_t rows = 4 * m - 3;
  const std::size_t ld = kBand + 1;
  std::fill(band_.begin(), band_.begin() + static_cast<std::ptrdiff_t>(ld * rows), 0.0);
  auto add = [this, ld](std::size_t p, std::size_t q, double value)
  {
    if (p < q)
    {
      std::swap(p, q);
    }
    band_[(p - q) + q * ld] += value;
  };
  // Each particle adds w g_p . g_q for every pair of rows whose constraints it takes part in.
  Gradient g[11];
  for (std::size_t l = 0; l <= m; ++l)
  {
    const double w = cable.inv_mass[f + l];
    if (w == 0.0)
    {
      continue;
    }
    int count = 0;
    if (l >= 1 && on_[l - 1] > 0.0)
    {
      g[count++] = {4 * (l - 1), true, 1.0, l - 1, 0};
    }
    if (l < m && on_[l] > 0.0)
    {
      g[count++] = {4 * l, true, -1.0, l, 0};
    }
    auto bend = [&](std::size_t k, double c)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        g[count++] = {4 * k + 1 + static_cast<std::size_t>(axis), false, c, 0, axis};
      }
    };
    if (l >= 2)
    {
      bend(l - 2, 1.0 / cable.rest[f + l - 1]);
    }
    if (l >= 1 && l + 1 <= m)
    {
      bend(l - 1, -(1.0 / cable.rest[f + l - 1] + 1.0 / cable.rest[f + l]));
    }
    if (l + 2 <= m)
    {
      bend(l, 1.0 / cable.rest[f + l]);
    }
    for (int p = 0; p < count; ++p)
    {
      for (int q = 0; q <= p; ++q)
      {
        const Gradient& a = g[p];
        const Gradient& b = g[q];
        double dot;
        if (a.stretch && b.stretch)
        {
          dot = a.sign_or_coefficient * b.sign_or_coefficient *
                (nx_[a.segment] * nx_[b.segment] + ny_[a.segment] * ny_[b.segment] + nz_[a.segment] * nz_[b.segment]);
        }
        else if (a.stretch != b.stretch)
        {
          const Gradient& s = a.stretch ? a : b;
          const Gradient& c = a.stretch ? b : a;
          const double n_axis = c.axis == 0 ? nx_[s.segment] : c.axis == 1 ? ny_[s.segment] : nz_[s.segment];
          dot = s.sign_or_coefficient * n_axis * c.sign_or_coefficient;
        }
        else
        {
          dot = a.axis == b.axis ? a.sign_or_coefficient * b.sign_or_coefficient : 0.0;
        }
        if (dot != 0.0)
        {
          add(a.row, b.row, w * dot);
        }
      }
    }
  }
  for (std::size_t k = 0; k < m; ++k)
  {
    const double lam = lambda.stretch[f + k];
    double& diagonal = band_[4 * k * ld];
    if (on_[k] > 0.0)
    {
      diagonal += stretch_alpha_[k];
      rhs_[4 * k] = stretch_c_[k] - stretch_alpha_[k] * lam;
    }
    else
    {
      diagonal = 1.0;
      rhs_[4 * k] = -lam;
    }
    for (int axis = 0; k + 1 < m && axis < 3; ++axis)
    {
      const std::size_t row = 4 * k + 1 + static_cast<std::size_t>(axis);
      double& d = band_[row * ld];
      d += bend_alpha_[k];
      rhs_[row] = bend_c_[3 * k + axis] - bend_alpha_[k] * bend_lambda_[3 * k + axis];
      if (!(d > kTinyDiagonal))
      {
        d = 1.0;  // no free particle in this bending constraint
        rhs_[row] = 0.0;
      }
    }
  }
}

void DirectSolver::solveTridiagonal(std::size_t rows)
{
  const bool ok = linear_ == LinearSolve::kLapack
                      ? banded::solveTridiagonalLapack(diag_.data(), off_.data(), rhs_.data(), rows)
                      : banded::solveTridiagonalSweep(diag_.data(), off_.data(), rhs_.data(), rows);
  if (!ok)
  {
    std::fill(rhs_.begin(), rhs_.begin() + static_cast<std::ptrdiff_t>(rows), 0.0);  // no move this iteration
  }
}

void DirectSolver::solveBanded(std::size_t rows)
{
  const bool ok = linear_ == LinearSolve::kLapack ? banded::solveBandedLapack(band_.data(), kBand, rhs_.data(), rows)
                                                  : banded::solveBandedSweep(band_.data(), kBand, rhs_.data(), rows);
  if (!ok)
  {
    std::fill(rhs_.begin(), rhs_.begin() + static_cast<std::ptrdiff_t>(rows), 0.0);
  }
}

}  // namespace rov_tether
