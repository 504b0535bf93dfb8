#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

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
inline void projectJointAnisotropic(Cable& cable, std::size_t j, double inv_ei_h2, double* mu)
{
  const std::size_t p[3] = {j, j + 1, j + 2};
  const double la = cable.rest[j];
  const double lb = cable.rest[j + 1];
  const double g[3] = {1.0 / la, -(1.0 / la + 1.0 / lb), 1.0 / lb};
  const double gamma = 0.5 * (la + lb) * inv_ei_h2;
  Eigen::Matrix3d s = gamma * Eigen::Matrix3d::Identity();
  Eigen::Vector3d c(mu[0], mu[1], mu[2]);
  c *= gamma;
  Eigen::Vector3d t[3];
  for (std::size_t i = 0; i < 3; ++i)
  {
    t[i] = Eigen::Vector3d(cable.tx[p[i]], cable.ty[p[i]], cable.tz[p[i]]);
    const double w = cable.inv_mass[p[i]];
    const double extra = cable.inv_mass_along[p[i]] - w;
    s += g[i] * g[i] * (w * Eigen::Matrix3d::Identity() + extra * t[i] * t[i].transpose());
    c += g[i] * cable.position(p[i]);
  }
  const Eigen::Vector3d d = s.llt().solve(-c);
  for (std::size_t i = 0; i < 3; ++i)
  {
    const double w = cable.inv_mass[p[i]];
    const double extra = cable.inv_mass_along[p[i]] - w;
    const Eigen::Vector3d move = g[i] * (w * d + extra * t[i].dot(d) * t[i]);
    cable.x[p[i]] += move.x(), cable.y[p[i]] += move.y(), cable.z[p[i]] += move.z();
  }
  mu[0] += d.x(), mu[1] += d.y(), mu[2] += d.z();
}

}  // namespace rov_tether
