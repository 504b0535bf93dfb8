#pragma once

#include <cmath>

#include "rov_tether/core/cable.hpp"
#include "simd.hpp"

namespace rov_tether
{

/**
 * xpbd's bending with stiffness EI: at the joint between segments j and j+1 (particles a = j, b = j+1,
 * c = j+2) the vector constraint "change of tangent"
 *   C = (x_c - x_b) / L_b - (x_b - x_a) / L_a,      |C| = the turning angle for small angles,
 * with compliance Lbar / EI (Lbar the mean of L_a and L_b), whose energy EI |C|^2 / (2 Lbar) is the discrete
 * elastic rod's: linear in the angle, as the paper's (i, i+2) distance constraint is not (its energy grows as
 * the angle to the fourth power). C is linear in the positions, with gradients g = (1/L_a, -(1/L_a + 1/L_b),
 * 1/L_b) times the identity; one XPBD projection (Macklin et al. 2016) of its three components at once:
 *   dmu = -(C + gamma mu) / (sum g_i^2 w_i + gamma),   x_i += w_i g_i dmu,   gamma = Lbar / (EI h^2).
 * The direct solver has the same constraint with an exact solve (direct_solver.hpp).
 */
ROV_TETHER_INLINE void projectJoint(double& ax, double& ay, double& az, double wa, double& bx, double& by, double& bz,
                                    double wb, double& cx, double& cy, double& cz, double wc, double la, double lb,
                                    double& mx, double& my, double& mz, double inv_ei_h2)
{
  const double ga = 1.0 / la;
  const double gc = 1.0 / lb;
  const double gb = -(ga + gc);
  const double gamma = 0.5 * (la + lb) * inv_ei_h2;
  const double inverse = 1.0 / (ga * ga * wa + gb * gb * wb + gc * gc * wc + gamma);
  const double dx = -(ga * ax + gb * bx + gc * cx + gamma * mx) * inverse;
  const double dy = -(ga * ay + gb * by + gc * cy + gamma * my) * inverse;
  const double dz = -(ga * az + gb * bz + gc * cz + gamma * mz) * inverse;
  mx += dx, my += dy, mz += dz;
  const double sa = wa * ga, sb = wb * gb, sc = wc * gc;
  ax += sa * dx, ay += sa * dy, az += sa * dz;
  bx += sb * dx, by += sb * dy, bz += sb * dz;
  cx += sc * dx, cy += sc * dy, cz += sc * dz;
}

/// projectJoint for a cable lighter along than across (added mass): particle i's inverse mass is
/// W_i = w_i I + dw_i t_i t_i^T, so the projection solves (sum g_i^2 W_i + gamma I) dmu = -(C + gamma mu)
/// and moves x_i by g_i W_i dmu. Joint j of the cable's own arrays; mu holds its three multipliers.
/// The 3x3 system is solved by its Cholesky factor in scalars, in the operations and order of Eigen's
/// LLT (unblocked, then the two triangular solves), so it rounds as that did. Written out because Eigen's
/// took 80% of an xpbd step with bending and added mass, and made such a step 35x slower under the
/// sanitizers (docs/benchmarks.md).
inline void projectJointAnisotropic(Cable& cable, std::size_t j, double inv_ei_h2, double* mu)
{
  const std::size_t p[3] = {j, j + 1, j + 2};
  const double la = cable.rest[j];
  const double lb = cable.rest[j + 1];
  const double g[3] = {1.0 / la, -(1.0 / la + 1.0 / lb), 1.0 / lb};
  const double gamma = 0.5 * (la + lb) * inv_ei_h2;
  // The lower triangle of s = gamma I + sum g_i^2 (w_i I + dw_i t_i t_i^T), and c = gamma mu + C.
  double s00 = gamma, s10 = 0.0, s11 = gamma, s20 = 0.0, s21 = 0.0, s22 = gamma;
  double c[3] = {mu[0] * gamma, mu[1] * gamma, mu[2] * gamma};
  double t[3][3];
  for (std::size_t i = 0; i < 3; ++i)
  {
    const std::size_t q = p[i];
    t[i][0] = cable.tx[q], t[i][1] = cable.ty[q], t[i][2] = cable.tz[q];
    const double w = cable.inv_mass[q];
    const double extra = cable.inv_mass_along[q] - w;
    const double gg = g[i] * g[i];
    const double e[3] = {extra * t[i][0], extra * t[i][1], extra * t[i][2]};
    s00 += gg * (w + e[0] * t[i][0]);
    s10 += gg * (0.0 + e[1] * t[i][0]);
    s11 += gg * (w + e[1] * t[i][1]);
    s20 += gg * (0.0 + e[2] * t[i][0]);
    s21 += gg * (0.0 + e[2] * t[i][1]);
    s22 += gg * (w + e[2] * t[i][2]);
    c[0] += g[i] * cable.x[q], c[1] += g[i] * cable.y[q], c[2] += g[i] * cable.z[q];
  }
  // s = L L^T, column by column.
  const double l00 = std::sqrt(s00);
  const double l10 = s10 / l00, l20 = s20 / l00;
  const double l11 = std::sqrt(s11 - l10 * l10);
  const double l21 = (s21 - l20 * l10) / l11;
  const double l22 = std::sqrt(s22 - (l20 * l20 + l21 * l21));
  // L y = -c, then L^T d = y.
  const double y0 = -c[0] / l00;
  const double y1 = (-c[1] - l10 * y0) / l11;
  const double y2 = (-c[2] - (l20 * y0 + l21 * y1)) / l22;
  const double d2 = y2 / l22;
  const double d1 = (y1 - l21 * d2) / l11;
  const double d0 = (y0 - (l10 * d1 + l20 * d2)) / l00;
  for (std::size_t i = 0; i < 3; ++i)
  {
    const std::size_t q = p[i];
    const double w = cable.inv_mass[q];
    const double extra = cable.inv_mass_along[q] - w;
    const double along = extra * ((t[i][0] * d0 + t[i][1] * d1) + t[i][2] * d2);
    cable.x[q] += g[i] * (w * d0 + along * t[i][0]);
    cable.y[q] += g[i] * (w * d1 + along * t[i][1]);
    cable.z[q] += g[i] * (w * d2 + along * t[i][2]);
  }
  mu[0] += d0, mu[1] += d1, mu[2] += d2;
}

}  // namespace rov_tether
