// The direct solver's primal path (direct_primal.hpp): the step energy's gradient and Hessian, assembled by
// 3x3 blocks of particles (mass, segments' axial and geometric stiffness, the bending joints), and what stays
// the same through a step's Newton iterations. The Newton iteration itself is in direct_primal.cpp.
#include <algorithm>

#include "direct_primal.hpp"
#include "simd.hpp"

namespace rov_tether
{
namespace
{

/// The most a compressed segment's geometric stiffness may take off either end's mass in the Hessian: an
/// eighth, so a particle's two segments take at most 2 x 2 / 8 of it (a segment's block enters its two
/// particles as [1 -1; -1 1], eigenvalue 2).
constexpr double kCompressedShare = 0.125;

/// The curvature C_j = a x_j - (a + b) x_j+1 + b x_j+2 of each of `joints` joints (each axis; a and b the
/// inverse rest lengths of its two segments): linear in the positions. The energy, its gradient and
/// Hessian, and the force residual all read it from here.
ROV_TETHER_TARGET_CLONES void jointCurvatures(const double* __restrict x, const double* __restrict y,
                                              const double* __restrict z, const double* __restrict inv_rest,
                                              double* __restrict cx, double* __restrict cy, double* __restrict cz,
                                              std::size_t joints)
{
  for (std::size_t j = 0; j < joints; ++j)
  {
    const double a = inv_rest[j];
    const double b = inv_rest[j + 1];
    cx[j] = a * x[j] - (a + b) * x[j + 1] + b * x[j + 2];
    cy[j] = a * y[j] - (a + b) * y[j + 1] + b * y[j + 2];
    cz[j] = a * z[j] - (a + b) * z[j + 1] + b * z[j + 2];
  }
}

/// Adds segmentTerm's block `b` to `target`.
[[gnu::always_inline]] inline void addTo(double* target, const PrimalNewton::SegmentBlock& b)
{
  for (std::size_t i = 0; i < 9; ++i)
  {
    target[i] += b.entry(i);
  }
}

}  // namespace

void PrimalNewton::prepare(const Cable& cable)
{
  // Each particle's mass (0 pinned) and its extra along the cable (m_along - m_across, with added mass), and
  // each segment's axial stiffness 1 / alpha: one division each a step, not one an iteration.
  const std::size_t f = ws_.first;
  for (std::size_t l = 0; l <= ws_.m; ++l)
  {
    const double w = cable.inv_mass[f + l];
    mass_[l] = w > 0.0 ? 1.0 / w : 0.0;
    mass_less_[l] = w > 0.0 && cable.anisotropic ? 1.0 / cable.inv_mass_along[f + l] - mass_[l] : 0.0;
  }
  for (std::size_t k = 0; k < ws_.m; ++k)
  {
    stiffness_[k] = 1.0 / ws_.alpha[k];
  }
  if (ws_.bending)
  {
    prepareBending(cable);
  }
  curvature(cable);
}

void PrimalNewton::curvature(const Cable& cable)
{
  if (ws_.bending)
  {
    jointCurvatures(cable.x.data() + ws_.first, cable.y.data() + ws_.first, cable.z.data() + ws_.first,
                    ws_.inv_rest.data(), curve_x_.data() + 2, curve_y_.data() + 2, curve_z_.data() + 2, ws_.m - 1);
  }
}

[[gnu::always_inline]] inline bool PrimalNewton::segmentTerm(const Cable& cable, std::size_t k, double* lam,
                                                             SegmentBlock* block) const
{
  // The segments of the model: all of a rod's; of a cable's, those the step stretches (solveModel); the
  // spool segment on the drum's piece.
  const std::size_t f = ws_.first;
  const double* w = cable.inv_mass.data() + f;
  // A particle's largest inverse mass (along the cable, where added mass does not act).
  auto mobility = [&](std::size_t l) { return cable.anisotropic ? std::max(w[l], cable.inv_mass_along[f + l]) : w[l]; };
  *lam = ws_.c[k] / ws_.alpha[k];
  double axial = stiffness_[k];
  if (k == 0 && ws_.drum != nullptr)
  {
    // The spool segment's force is the drum's law, solved for in solveModel: here only its geometric
    // stiffness.
    *lam = 0.0;
    axial = 0.0;
  }
  else if (inMiddle(k))
  {
    // The dashpot's middle piece of a slack segment: its force and slope (DirectWorkspace::begin).
    *lam = ws_.middleForce(k, ws_.c[k]);
    axial = ws_.dashpot[k];
  }
  else if (!(ws_.on()[k] > 0.0))
  {
    return false;
  }
  const double n[3] = {ws_.nx[k], ws_.ny[k], ws_.nz[k]};
  // Hessian of the segment's energy: axial (1 / alpha) n n^T plus the geometric stiffness
  // lambda / |d| (I - n n^T) of the Newton estimate of lambda (not C / alpha, which a stiff segment's
  // rounding makes useless). In compression it is negative: kept while it is at most kCompressedShare of
  // the mass of either end (then each particle's two segments take at most half its mass off the
  // Hessian's smallest eigenvalue, which stays positive), dropped beyond (a rod buckling). Dropped always,
  // a cable lying slack on a seabed converged linearly: 4 iterations a step instead of 2.
  double geometric = ws_.len[k] > 0.0 ? lambda_[k] / ws_.len[k] : 0.0;
  if (geometric < 0.0 && !(-geometric * std::max(mobility(k), mobility(k + 1)) <= kCompressedShare))
  {
    geometric = 0.0;
  }
  block->scale = axial - geometric, block->geometric = geometric;
  block->n[0] = n[0], block->n[1] = n[1], block->n[2] = n[2];
  return true;
}

void PrimalNewton::assemble(const Cable& cable)
{
  // The Hessian by 3x3 blocks of particles, a block row at a time: diagonal (l, l), first below (l + 1, l),
  // second below (l + 2, l, with bending: a multiple of the identity). A pinned particle's row is the
  // identity, and nothing couples to it. Each block is written whole (no clearing pass), its terms added in
  // a fixed order: the mass, segment l - 1, segment l, then the bending joints l - 2, l - 1, l.
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  const double* w = cable.inv_mass.data() + f;
  auto pinned = [w](std::size_t l) { return w[l] == 0.0; };
  SegmentBlock before;  // segment l - 1's, when in the model
  double before_lam = 0.0;
  bool before_on = false;
  for (std::size_t l = 0; l <= m; ++l)
  {
    // The row's diagonal block and gradient are summed in locals and stored once, and the segments' blocks
    // are values, not arrays indexed by the row: in memory, their scalar stores were read back by vectorised
    // sums as 16-byte loads, a store-forwarding stall each (a fifth of the assembly's time).
    double diagonal[9];
    double g[3];
    SegmentBlock here;
    double here_lam = 0.0;
    const bool here_on = l < m && segmentTerm(cable, l, &here_lam, &here);
    if (pinned(l))
    {
      static constexpr double kIdentity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      std::copy(kIdentity, kIdentity + 9, diagonal);
      g[0] = g[1] = g[2] = 0.0;
    }
    else
    {
      massTerm(cable, l, diagonal, g);
      if (before_on)
      {
        // dC/dx_k+1 = +n_k: the gradient gets J^T lambda.
        addTo(diagonal, before);
        g[0] += before_lam * ws_.nx[l - 1], g[1] += before_lam * ws_.ny[l - 1], g[2] += before_lam * ws_.nz[l - 1];
      }
      if (here_on)
      {
        addTo(diagonal, here);
        g[0] -= here_lam * ws_.nx[l], g[1] -= here_lam * ws_.ny[l], g[2] -= here_lam * ws_.nz[l];
      }
    }
    if (l < m)
    {
      double* below = &hessian_first_[9 * l];
      if (here_on && !pinned(l) && !pinned(l + 1))
      {
        for (std::size_t i = 0; i < 9; ++i)
        {
          below[i] = 0.0 + -1.0 * here.entry(i);
        }
      }
      else
      {
        std::fill(below, below + 9, 0.0);
      }
    }
    if (ws_.bending && !pinned(l))
    {
      bendingTerms(l, diagonal, g);
    }
    for (std::size_t i = 0; i < 9; ++i)
    {
      hessian_diag_[9 * l + i] = diagonal[i];
    }
    for (std::size_t a = 0; a < 3; ++a)
    {
      grad_[3 * l + a] = g[a];
    }
    before = here;
    before_on = here_on;
    before_lam = here_lam;
  }
}

[[gnu::always_inline]] inline void PrimalNewton::massTerm(const Cable& cable, std::size_t l, double* diagonal,
                                                          double* g) const
{
  // The particle's mass matrix: m_across I, plus (m_along - m_across) t t^T with added mass.
  const std::size_t f = ws_.first;
  const double mass = mass_[l];
  const double d[3] = {cable.x[f + l] - ws_.xt[l], cable.y[f + l] - ws_.yt[l], cable.z[f + l] - ws_.zt[l]};
  for (std::size_t i = 0; i < 9; ++i)
  {
    diagonal[i] = i % 4 == 0 ? mass : 0.0;
  }
  if (!cable.anisotropic)
  {
    g[0] = mass * d[0], g[1] = mass * d[1], g[2] = mass * d[2];
    return;
  }
  const double t[3] = {cable.tx[f + l], cable.ty[f + l], cable.tz[f + l]};
  const double less = mass_less_[l];
  for (std::size_t a = 0; a < 3; ++a)
  {
    for (std::size_t c = 0; c < 3; ++c)
    {
      diagonal[3 * a + c] += less * t[a] * t[c];
    }
  }
  for (std::size_t a = 0; a < 3; ++a)
  {
    g[a] = diagonal[3 * a] * d[0] + diagonal[3 * a + 1] * d[1] + diagonal[3 * a + 2] * d[2];
  }
}

void PrimalNewton::prepareBending(const Cable& cable)
{
  // Joint j (after particle j) has the curvature C_j = a x_j - (a + b) x_j+1 + b x_j+2 (curvature()), linear
  // in the positions with weights (a, -(a + b), b), so its Hessian is constant within a step: g_r g_s / gamma
  // times the identity. Particle l is the r-th of joint l - r; its terms are laid out in the order assemble
  // adds them (joints l - 2, l - 1, l), 0 where there is no such joint or the particle is pinned (adding 0
  // changes nothing). The curvature arrays are offset by 2, with zeros for the joints -2, -1, m - 1 and m.
  const std::size_t m = ws_.m;
  const double* w = cable.inv_mass.data() + ws_.first;
  auto weight = [this](std::size_t j, std::size_t r)
  {
    const double a = ws_.inv_rest[j], b = ws_.inv_rest[j + 1];
    return r == 0 ? a : r == 1 ? -(a + b) : b;
  };
  auto joint = [m](std::size_t l, std::size_t r) { return l >= r && l - r + 1 < m; };  // joint l - r exists
  for (std::size_t l = 0; l <= m; ++l)
  {
    const bool free_l = w[l] != 0.0;
    for (std::size_t i = 0; i < 3; ++i)
    {
      const std::size_t r = 2 - i;
      const bool on = free_l && joint(l, r);
      const double gr = on ? weight(l - r, r) : 0.0;
      const double inv = on ? ws_.inv_gamma[l - r] : 0.0;
      bend_weight_[3 * l + i] = gr;
      bend_inv_[3 * l + i] = inv;
      bend_diag_[3 * l + i] = gr * gr * inv;
    }
    const bool pair = l + 1 <= m && free_l && w[l + 1] != 0.0;  // the block (l + 1, l) couples two free ones
    for (std::size_t i = 0; i < 2; ++i)
    {
      const std::size_t s = 1 - i;
      bend_first_[2 * l + i] =
          pair && joint(l, s) ? weight(l - s, s + 1) * weight(l - s, s) * ws_.inv_gamma[l - s] : 0.0;
    }
    if (l + 2 <= m)
    {
      hessian_second_[l] =
          l + 1 < m && free_l && w[l + 2] != 0.0 ? weight(l, 2) * weight(l, 0) * ws_.inv_gamma[l] : 0.0;
    }
  }
}

[[gnu::always_inline]] inline void PrimalNewton::bendingTerms(std::size_t l, double* diagonal, double* g)
{
  // prepareBending's terms of row l, each added in its order (particle l's joints l - 2, l - 1, l).
  const double* v = &bend_diag_[3 * l];
  const double* weight = &bend_weight_[3 * l];
  const double* inv = &bend_inv_[3 * l];
  const double* cx = &curve_x_[l];  // joint l - 2 (the arrays are offset by 2)
  const double* cy = &curve_y_[l];
  const double* cz = &curve_z_[l];
  for (std::size_t i = 0; i < 3; ++i)
  {
    diagonal[0] += v[i], diagonal[4] += v[i], diagonal[8] += v[i];
    g[0] += weight[i] * cx[i] * inv[i], g[1] += weight[i] * cy[i] * inv[i], g[2] += weight[i] * cz[i] * inv[i];
  }
  if (l < ws_.m)
  {
    double* below = &hessian_first_[9 * l];
    const double* u = &bend_first_[2 * l];
    for (std::size_t i = 0; i < 2; ++i)
    {
      below[0] += u[i], below[4] += u[i], below[8] += u[i];
    }
  }
}

}  // namespace rov_tether
