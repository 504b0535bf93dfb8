#include "direct_workspace.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rov_tether/core/spool.hpp"
#include "simd.hpp"

namespace rov_tether
{
namespace
{

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

/// Each of m segments' compliance alpha = L / (EA h^2) (`stiffness` EA h^2), 1 / L and the length its law
/// stops at (L: no dashpot shifts it), as DirectWorkspace::begin's general loop gives them without axial
/// damping or sections: the same numbers (there EA h^2 + 0 and L + 0 x 0, which are EA h^2 and L exactly).
ROV_TETHER_TARGET_CLONES void undampedSegments(const double* __restrict rest, double stiffness, std::size_t m,
                                               double* __restrict alpha, double* __restrict inv_rest,
                                               double* __restrict stop)
{
#pragma omp simd
  for (std::size_t k = 0; k < m; ++k)
  {
    alpha[k] = rest[k] / stiffness;
    inv_rest[k] = 1.0 / rest[k];
    stop[k] = rest[k];
  }
}

/// The end of a step for each of m segments: a cable's multiplier clamped at 0 (a slack segment carries
/// nothing, exactly: its multiplier can end a rounding below 0), whether it ended taut, and the largest
/// multiplier over the weight of its length (lambda / (w L), for a segment with a weight and a length).
/// Branch-free, so that it vectorises; the largest is exact in any order.
ROV_TETHER_TARGET_CLONES double endSegments(double* __restrict lambda, unsigned char* __restrict taut,
                                            const double* __restrict weight, const double* __restrict len,
                                            std::size_t m, bool unilateral)
{
  double ratio = 0.0;
#pragma omp simd reduction(max : ratio)
  for (std::size_t k = 0; k < m; ++k)
  {
    const double own = lambda[k];
    const double clamped = std::max(own, 0.0);
    const double lam = unilateral ? clamped : own;
    lambda[k] = lam;
    taut[k] = lam > 0.0 ? 1 : 0;
    const double pulled = weight[k] * len[k];
    const double share = lam / (pulled > 0.0 ? pulled : 1.0);  // kept from dividing by 0 where it is not used
    const double counted = weight[k] > 0.0 && len[k] > 0.0 ? share : 0.0;
    ratio = std::max(ratio, counted);
  }
  return ratio;
}

}  // namespace

void DirectWorkspace::reserve(std::size_t n)
{
  if (nx.size() >= n)
  {
    return;
  }
  for (auto* v : {&xt,    &yt,        &zt,       &sx,          &sy,           &sz,           &nx,          &ny,
                  &nz,    &len,       &c,        &alpha,       &stop,         &kink,         &dashpot,     &zero,
                  &gamma, &inv_gamma, &inv_rest, &warm_lambda, &correction_x, &correction_y, &correction_z})
  {
    v->assign(n, 0.0);
  }
  on_padded.assign(n + 2, 0.0);  // padded by one zero on each side
  taut.assign(n, 0);
}

void DirectWorkspace::begin(const Cable& cable, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  first = f;
  m = n - 1 - f;
  std::copy(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f), lambda.stretch.end(), warm_lambda.begin() + f);
  std::fill(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(f), lambda.stretch.end(), 0.0);
  std::fill(lambda.bend.begin() + static_cast<std::ptrdiff_t>(std::min(f, lambda.bend.size())), lambda.bend.end(), 0.0);
  bending = settings.elasticBending() && m >= 2;
  unilateral = !bending;
  nominal = cable.rest[n - 2];
  const double h = settings.time_step;
  const double h2 = h * h;
  // Kelvin-Voigt, backward Euler: a taut segment's force T = (EA C + BA (C - C_0) / h) / L, C_0 its stretch
  // at the step's start (from px), is lambda = T h^2, that is C - s = alpha lambda with alpha = L / (EA h^2 +
  // BA h) and s = BA / (h EA + BA) C_0: the undamped law with a softer compliance about a shifted rest
  // length (a rod's, two-sided, carries compression). BA = 0: s = 0 and the undamped alpha. The spool segment is
  // left undamped: the winch changes its rest length before the step (pay-out, reel-in), which px's length
  // does not know, and a drum's law replaces its elastic one.
  // A cable's dashpot pulls when it is slack too, as MoorDyn's: a slack segment (C_0 < 0) pulled straight
  // carries BA (e - e_0) / (h L) before it is taut, so a snap is spread over the time the slack takes to
  // close, not an impulse over one step. Its spring is one-sided, and the sum is never below 0 (the cable
  // does not push). In C (= e - s, s = BA / (h EA + BA) C_0) that is a three-piece convex law: C / alpha
  // above the kink -s (e = 0), the dashpot's slope BA h / L below it down to where its force is 0
  // (e = e_0), 0 below that. A segment taut at the start (C_0 >= 0) has no middle piece: its dashpot's
  // push would take the sum below 0 at once.
  const double damping = settings.axial_damping;
  const double shift_share = settings.dampingShiftShare();
  dashpots = false;
  // Sections (CableLoading): each segment's own EA and BA, and each joint's EI.
  const CableLoading& load = cable.loading;
  const bool loaded = !load.empty();
  const double* rest_lengths = cable.rest.data() + f;
  const bool undamped = !loaded && !(shift_share > 0.0);  // no dashpot anywhere: the general loop's zeros left out
  if (undamped)
  {
    undampedSegments(rest_lengths, settings.axial_stiffness * h2, m, alpha.data(), inv_rest.data(), stop.data());
    std::fill(kink.begin(), kink.begin() + static_cast<std::ptrdiff_t>(m), 0.0);
    std::fill(dashpot.begin(), dashpot.begin() + static_cast<std::ptrdiff_t>(m), 0.0);
    std::fill(zero.begin(), zero.begin() + static_cast<std::ptrdiff_t>(m), 0.0);
  }
  else
  {
    for (std::size_t k = 0; k < m; ++k)
    {
      const double rest = cable.rest[f + k];
      const double own_damping = loaded && shift_share > 0.0 ? load.axial_damping[f + k] : damping;
      const double own_stiffness = loaded ? load.axial_stiffness[f + k] : settings.axial_stiffness;
      const double share =
          loaded && own_damping > 0.0 ? own_damping / (h * own_stiffness + own_damping) : (loaded ? 0.0 : shift_share);
      const bool damped = share > 0.0 && k > 0;
      alpha[k] = rest / (own_stiffness * h2 + (damped ? own_damping * h : 0.0));
      inv_rest[k] = 1.0 / rest;
      const double start = damped ? cable.startLength(f + k) - rest : 0.0;
      stop[k] = rest + share * start;
      const bool middle = damped && unilateral && start < 0.0;
      kink[k] = middle ? -share * start : 0.0;
      dashpot[k] = middle ? own_damping * h / rest : 0.0;
      zero[k] = middle ? start * (1.0 - share) : 0.0;
      dashpots = dashpots || middle;
    }
  }
  const std::size_t joints = bending ? m - 1 : 0;  // m >= 2 with bending
  if (loaded)
  {
    for (std::size_t k = 0; k < joints; ++k)
    {
      // The joint's two half segments in series: each half's compliance L / (2 EI) (a segment of EI 0 is a
      // hinge: infinite compliance).
      gamma[k] = (0.5 * cable.rest[f + k] / load.bending_stiffness[f + k] +
                  0.5 * cable.rest[f + k + 1] / load.bending_stiffness[f + k + 1]) /
                 h2;
    }
  }
  else
  {
    const double bending_h2 = settings.bending_stiffness * h2;
#pragma omp simd
    for (std::size_t k = 0; k < joints; ++k)
    {
      gamma[k] = 0.5 * (rest_lengths[k] + rest_lengths[k + 1]) / bending_h2;
    }
  }
  std::copy(cable.x.begin() + static_cast<std::ptrdiff_t>(f), cable.x.end(), xt.begin());
  std::copy(cable.y.begin() + static_cast<std::ptrdiff_t>(f), cable.y.end(), yt.begin());
  std::copy(cable.z.begin() + static_cast<std::ptrdiff_t>(f), cable.z.end(), zt.begin());
  geometry(cable);
  drum = settings.drum;
  if (drum != nullptr)
  {
    drum->prepare(alpha[0]);
    if (bending)
    {
      // The spool segment lengthens by the drum's pay-out within the solve, which its rest length does not
      // know: the joint's curvature a x_0 - (a + b) x_1 + b x_2 would read that as a kink and pull along the
      // cable (2 N at 1 m/s with EI 0.2). The cable leaves the spool over a sheave: a hinge there.
      gamma[0] = std::numeric_limits<double>::infinity();
      if (m >= 3)
      {
        // The joint after it was that hinge until the last particle left the spool, at whatever angle the
        // hinge let the cable take there; at full stiffness at once it would kick the cable (a spike above
        // an auto-tension winch's stall pull at each release, and the drum slipping out). Its stiffness comes
        // in as the spool segment grows from half a segment (just after a release) to one and a half (the
        // next release), so it is continuous through releases and take-backs alike.
        const double grown = cable.rest[f] / cable.rest[f + 1] - Spool::kMinFirst;
        gamma[1] /= std::clamp(grown, 0.0, 1.0);  // infinite (a hinge) at 0
      }
    }
  }
#pragma omp simd
  for (std::size_t k = 0; k < joints; ++k)
  {
    inv_gamma[k] = 1.0 / gamma[k];  // 0 at a hinge
  }
}

void DirectWorkspace::end(const Cable& cable, double* lambda)
{
  const std::size_t f = first;
  if (drum != nullptr)
  {
    if (cable.inv_mass[f] + cable.inv_mass[f + 1] == 0.0)
    {
      lambda[0] = drum->force(c[0]);  // a segment nothing can move: the law alone
    }
    drum->payout = drum->payoutAt(c[0]);
  }
  for (std::size_t l = 0; l <= m; ++l)
  {
    correction_x[f + l] = cable.x[f + l] - xt[l];
    correction_y[f + l] = cable.y[f + l] - yt[l];
    correction_z[f + l] = cable.z[f + l] - zt[l];
  }
  std::fill(taut.begin(), taut.begin() + static_cast<std::ptrdiff_t>(f), 0);
  std::fill(taut.begin() + static_cast<std::ptrdiff_t>(f + m), taut.end(), 0);
  tension_ratio = endSegments(lambda, taut.data() + f, cable.stretch_weight.data() + f, len.data(), m, unilateral);
}

void DirectWorkspace::forget()
{
  std::fill(taut.begin(), taut.end(), 0);
  for (auto* v : {&correction_x, &correction_y, &correction_z})
  {
    std::fill(v->begin(), v->end(), 0.0);
  }
  tension_ratio = 0.0;
}

void DirectWorkspace::geometry(const Cable& cable)
{
  const std::size_t f = first;
  segmentGeometry(cable.x.data() + f, cable.y.data() + f, cable.z.data() + f, stop.data(), nx.data(), ny.data(),
                  nz.data(), len.data(), c.data(), m);
}

void DirectWorkspace::save(const Cable& cable)
{
  const auto f = static_cast<std::ptrdiff_t>(first);
  std::copy(cable.x.begin() + f, cable.x.end(), sx.begin());
  std::copy(cable.y.begin() + f, cable.y.end(), sy.begin());
  std::copy(cable.z.begin() + f, cable.z.end(), sz.begin());
}

void DirectWorkspace::restore(Cable& cable) const
{
  const auto f = static_cast<std::ptrdiff_t>(first);
  const auto count = static_cast<std::ptrdiff_t>(m + 1);
  std::copy(sx.begin(), sx.begin() + count, cable.x.begin() + f);
  std::copy(sy.begin(), sy.begin() + count, cable.y.begin() + f);
  std::copy(sz.begin(), sz.begin() + count, cable.z.begin() + f);
}

}  // namespace rov_tether
