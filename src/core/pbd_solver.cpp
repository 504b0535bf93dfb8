#include "rov_tether/core/pbd_solver.hpp"

#include <algorithm>
#include <cmath>

#include "joint_bending.hpp"
#include "simd.hpp"

namespace rov_tether
{
namespace
{

/// Added to squared lengths before the division, far below any real length [m^2].
constexpr double kMinLengthSquared = 1e-24;

/**
 * Projects `count` distance constraints, constraint k joining particle k of the `a` arrays with particle
 * k of the `b` arrays. Constraint data (rest, weight, lambda) is indexed by k. The a and b ranges must
 * not overlap, so the loop has no dependency between iterations and vectorises.
 *
 * kPower 0 is PBD (rigid), its correction scaled by `relax` (successive over-relaxation; 1 = the paper's). kPower 1 is
 * XPBD with the compliance alpha~ = compliance * alpha_len (already divided by dt^2): the multiplier increment is
 * (C - alpha~ lambda) / (w_a + w_b + alpha~) with C = |d| - stop. Undamped, alpha_len and stop are the rest
 * lengths; with axial damping (Kelvin-Voigt), PbdSolver::dampedLengths.
 */
template <int kPower>
ROV_TETHER_INLINE void projectPairs(double* __restrict ax, double* __restrict ay, double* __restrict az,
                                    const double* __restrict aw, double* __restrict bx, double* __restrict by,
                                    double* __restrict bz, const double* __restrict bw, const double* __restrict rest,
                                    const double* __restrict weight, double* __restrict lambda, std::size_t count,
                                    double compliance = 0.0, double relax = 1.0,
                                    const double* __restrict stop = nullptr,
                                    const double* __restrict alpha_len = nullptr)
{
  for (std::size_t k = 0; k < count; ++k)
  {
    const double dx = bx[k] - ax[k];
    const double dy = by[k] - ay[k];
    const double dz = bz[k] - az[k];
    const double length_squared = dx * dx + dy * dy + dz * dz;
    // Branch-free so the loop vectorises; a zero-length constraint has d = 0 and so moves nothing.
    const double inv_length = 1.0 / std::sqrt(length_squared + kMinLengthSquared);
    double s;
    if constexpr (kPower == 0)
    {
      // Correction factor: (|d| - rest) / |d| / (w_a + w_b); multiplier increment s |d| [kg m].
      s = (1.0 - rest[k] * inv_length) * weight[k] * relax;
      lambda[k] += s * length_squared * inv_length;
    }
    else
    {
      const double alpha = compliance * alpha_len[k];
      const double delta =
          (length_squared * inv_length - stop[k] - alpha * lambda[k]) / (aw[k] + bw[k] + alpha + kMinLengthSquared);
      lambda[k] += delta;
      s = delta * inv_length;
    }
    const double move_a = aw[k] * s;
    const double move_b = bw[k] * s;
    ax[k] += move_a * dx;
    ay[k] += move_a * dy;
    az[k] += move_a * dz;
    bx[k] -= move_b * dx;
    by[k] -= move_b * dy;
    bz[k] -= move_b * dz;
  }
}

/**
 * One constraint between particles a and b of the cable's own arrays, as projectPairs, for a cable whose
 * particles are lighter along it than across it (added mass acts across only): particle i's inverse mass
 * is W_i = w_i I + dw_i t_i t_i^T (dw = inv_mass_along - inv_mass, t the tangent), so the constraint's
 * effective inverse mass is n . W_a n + n . W_b n and each particle moves by W_i n.
 */
template <int kPower>
void projectPairAnisotropic(Cable& cable, std::size_t a, std::size_t b, double rest, double& lambda, double compliance,
                            double relax, double stop = 0.0, double alpha_len = 0.0)
{
  const double dx = cable.x[b] - cable.x[a];
  const double dy = cable.y[b] - cable.y[a];
  const double dz = cable.z[b] - cable.z[a];
  const double length_squared = dx * dx + dy * dy + dz * dz;
  const double inv_length = 1.0 / std::sqrt(length_squared + kMinLengthSquared);
  const double extra_a = cable.inv_mass_along[a] - cable.inv_mass[a];
  const double extra_b = cable.inv_mass_along[b] - cable.inv_mass[b];
  const double da = (dx * cable.tx[a] + dy * cable.ty[a] + dz * cable.tz[a]);  // d . t_a
  const double db = (dx * cable.tx[b] + dy * cable.ty[b] + dz * cable.tz[b]);
  const double mobility =
      cable.inv_mass[a] + cable.inv_mass[b] + (extra_a * da * da + extra_b * db * db) * inv_length * inv_length;
  if (!(mobility > 0.0))
  {
    return;
  }
  double s;
  if constexpr (kPower == 0)
  {
    s = (1.0 - rest * inv_length) / mobility * relax;
    lambda += s * length_squared * inv_length;
  }
  else
  {
    const double alpha = compliance * alpha_len;
    const double delta = (length_squared * inv_length - stop - alpha * lambda) / (mobility + alpha);
    lambda += delta;
    s = delta * inv_length;
  }
  const double along_a = s * extra_a * da;
  const double along_b = s * extra_b * db;
  const double wa = s * cable.inv_mass[a];
  const double wb = s * cable.inv_mass[b];
  cable.x[a] += wa * dx + along_a * cable.tx[a];
  cable.y[a] += wa * dy + along_a * cable.ty[a];
  cable.z[a] += wa * dz + along_a * cable.tz[a];
  cable.x[b] -= wb * dx + along_b * cable.tx[b];
  cable.y[b] -= wb * dy + along_b * cable.ty[b];
  cable.z[b] -= wb * dz + along_b * cable.tz[b];
}

/// Number of constraints l = 4 k + r with l <= last, for k >= 0.
inline std::size_t countResidue(std::size_t r, std::size_t last_plus_one)
{
  return r < last_plus_one ? (last_plus_one - 1 - r) / 4 + 1 : 0;
}

/// Pointers into the blocked arrays of PbdSolver (see its documentation).
struct Blocked
{
  double* x;
  double* y;
  double* z;
  const double* w;
  const double* rest;
  const double* weight;
  double* lambda;
  const double* stop;       ///< xpbd: the length each stretch constraint holds (rest, or shifted by damping).
  const double* alpha_len;  ///< xpbd: compliance * alpha_len is the constraint's alpha~ (rest undamped).
  const double* bend_rest;
  const double* bend_weight;
  double* bend_lambda;
  double* joint_x;  ///< xpbd's joint bending: the three multipliers of joint l.
  double* joint_y;
  double* joint_z;
  std::size_t block;          ///< Length of one block.
  std::size_t particles;      ///< Deployed particles m.
  double stretch_compliance;  ///< XPBD: 1 / (EA dt^2) [1/(kg m)]; 0 = PBD.
  double inv_ei_h2;           ///< xpbd's joint bending: 1 / (EI dt^2); 0 = none.
  double relax;               ///< PBD over-relaxation factor.
};

/// Projects the constraints of residue r (constraint l = 4 k + r) between block r and the block of the
/// particle `span` further on (1 for stretch, 2 for bending).
ROV_TETHER_INLINE void projectResidue(const Blocked& c, std::size_t r, std::size_t span, bool bend, std::size_t count)
{
  const std::size_t a = r * c.block;
  const std::size_t b = ((r + span) & 3) * c.block + (r + span) / 4;  // particle 4 k + r + span
  const double* rest = (bend ? c.bend_rest : c.rest) + a;
  const double* weight = (bend ? c.bend_weight : c.weight) + a;
  double* lambda = (bend ? c.bend_lambda : c.lambda) + a;
  const double compliance = bend ? 0.0 : c.stretch_compliance;  // the paper's bending is pbd's only
  if (compliance == 0.0)
  {
    projectPairs<0>(c.x + a, c.y + a, c.z + a, c.w + a, c.x + b, c.y + b, c.z + b, c.w + b, rest, weight, lambda, count,
                    0.0, c.relax);
  }
  else
  {
    projectPairs<1>(c.x + a, c.y + a, c.z + a, c.w + a, c.x + b, c.y + b, c.z + b, c.w + b, rest, weight, lambda, count,
                    compliance, 1.0, c.stop + a, c.alpha_len + a);
  }
}

/// Projects xpbd's joints of residue r (joint l = 4 k + r, particles l, l + 1, l + 2 in blocks r, r + 1,
/// r + 2): joints of one residue share no particle.
ROV_TETHER_INLINE void projectJointResidue(const Blocked& c, std::size_t r, std::size_t count)
{
  const std::size_t a = r * c.block;
  const std::size_t b = ((r + 1) & 3) * c.block + (r + 1) / 4;
  const std::size_t d = ((r + 2) & 3) * c.block + (r + 2) / 4;
  double* __restrict ax = c.x + a;
  double* __restrict ay = c.y + a;
  double* __restrict az = c.z + a;
  double* __restrict bx = c.x + b;
  double* __restrict by = c.y + b;
  double* __restrict bz = c.z + b;
  double* __restrict dx = c.x + d;
  double* __restrict dy = c.y + d;
  double* __restrict dz = c.z + d;
  const double* wa = c.w + a;
  const double* wb = c.w + b;
  const double* wd = c.w + d;
  const double* la = c.rest + a;  // segment l
  const double* lb = c.rest + b;  // segment l + 1
  double* __restrict mx = c.joint_x + a;
  double* __restrict my = c.joint_y + a;
  double* __restrict mz = c.joint_z + a;
  for (std::size_t k = 0; k < count; ++k)
  {
    projectJoint(ax[k], ay[k], az[k], wa[k], bx[k], by[k], bz[k], wb[k], dx[k], dy[k], dz[k], wd[k], la[k], lb[k],
                 mx[k], my[k], mz[k], c.inv_ei_h2);
  }
}

ROV_TETHER_TARGET_CLONES
void solveBlocked(const Blocked& c, const SolverSettings& settings, bool bending)
{
  const std::size_t m = c.particles;
  std::size_t stretch_count[4];
  std::size_t bend_count[4];
  for (std::size_t r = 0; r < 4; ++r)
  {
    stretch_count[r] = countResidue(r, m - 1);            // stretch l in [0, m - 2]
    bend_count[r] = m >= 3 ? countResidue(r, m - 2) : 0;  // bending l in [0, m - 3]
  }
  for (int iteration = 0; iteration < settings.iterations; ++iteration)
  {
    // Even segments (residues 0 and 2 share no particle), then odd ones (1 and 3).
    for (std::size_t r : {0, 2, 1, 3})
    {
      projectResidue(c, r, 1, false, stretch_count[r]);
    }
    if (bending)
    {
      // Residues 0 and 1 share no particle, nor do 2 and 3.
      for (std::size_t r = 0; r < 4; ++r)
      {
        projectResidue(c, r, 2, true, bend_count[r]);
      }
    }
    if (c.inv_ei_h2 > 0.0)
    {
      for (std::size_t r = 0; r < 4; ++r)
      {
        projectJointResidue(c, r, bend_count[r]);
      }
    }
  }
}

void resetMultipliers(const Cable& state, Multipliers& lambda, std::size_t segments_end, std::size_t bends_end)
{
  std::fill(lambda.stretch.begin() + static_cast<std::ptrdiff_t>(state.first),
            lambda.stretch.begin() + static_cast<std::ptrdiff_t>(segments_end), 0.0);
  if (bends_end > state.first)
  {
    std::fill(lambda.bend.begin() + static_cast<std::ptrdiff_t>(state.first),
              lambda.bend.begin() + static_cast<std::ptrdiff_t>(bends_end), 0.0);
  }
}

}  // namespace

void PbdSolver::project(Cable& state, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t f = state.first;
  if (state.size() < f + 2)
  {
    return;
  }
  const std::size_t m = state.size() - f;
  // pbd: the paper's (i, i+2) bending constraints. xpbd: bending stiffness EI at the joints
  // (joint_bending.hpp), none without it.
  const bool bending = settings.bending && !compliant_;
  const double inv_dt2 = 1.0 / (settings.time_step * settings.time_step);
  const double stretch_compliance = compliant_ ? inv_dt2 / settings.axial_stiffness : 0.0;
  const bool joints = compliant_ && settings.elasticBending() && m >= 3;
  const double inv_ei_h2 = joints ? inv_dt2 / settings.bending_stiffness : 0.0;
  // Sized for the whole cable on the first step, whichever path runs: pay-out never reallocates.
  const std::size_t capacity = 4 * (state.size() / 4 + 2);
  if (x_.size() < capacity)
  {
    for (auto* v : {&x_, &y_, &z_, &inv_mass_, &rest_, &weight_, &lambda_, &bend_rest_, &bend_weight_, &bend_lambda_,
                    &joint_x_, &joint_y_, &joint_z_, &stop_, &alpha_len_})
    {
      v->assign(capacity, 0.0);
    }
  }
  const double relax = compliant_ ? 1.0 : settings.over_relaxation;
  const bool damped = compliant_ && settings.axial_damping > 0.0;
  // An anisotropic cable (added mass) is projected in place, constraint by constraint, in the same order.
  if (m <= direct_particles_ || state.anisotropic)
  {
    const double* stop = state.rest.data();
    const double* alpha_len = state.rest.data();
    if (damped)
    {
      if (cable_stop_.size() < state.size())  // sized for the whole cable once: pay-out never reallocates
      {
        cable_stop_.assign(state.size(), 0.0);
        cable_alpha_len_.assign(state.size(), 0.0);
      }
      for (std::size_t j = f; j + 1 < state.size(); ++j)
      {
        dampedLengths(state, j, settings, &cable_stop_[j], &cable_alpha_len_[j]);
      }
      stop = cable_stop_.data();
      alpha_len = cable_alpha_len_.data();
    }
    solveDirect(state, lambda, settings.iterations, bending, stretch_compliance, inv_ei_h2, relax, stop, alpha_len);
    copied_first_ = static_cast<std::size_t>(-1);  // the blocked copies are stale from here on
    return;
  }
  block_ = m / 4 + 2;  // room for particle 4 k + r + 2 one block further on
  copyIn(state, m);
  if (damped)
  {
    for (std::size_t l = 0; l + 1 < m; ++l)
    {
      dampedLengths(state, f + l, settings, &stop_[slot(l)], &alpha_len_[slot(l)]);
    }
  }
  const Blocked blocked{x_.data(),
                        y_.data(),
                        z_.data(),
                        inv_mass_.data(),
                        rest_.data(),
                        weight_.data(),
                        lambda_.data(),
                        damped ? stop_.data() : rest_.data(),
                        damped ? alpha_len_.data() : rest_.data(),
                        bend_rest_.data(),
                        bend_weight_.data(),
                        bend_lambda_.data(),
                        joint_x_.data(),
                        joint_y_.data(),
                        joint_z_.data(),
                        block_,
                        m,
                        stretch_compliance,
                        inv_ei_h2,
                        relax};
  solveBlocked(blocked, settings, bending);
  copyOut(state, lambda, m, bending);
}

void PbdSolver::dampedLengths(const Cable& state, std::size_t j, const SolverSettings& settings, double* stop,
                              double* alpha_len)
{
  // Kelvin-Voigt in XPBD's implicit step, as direct's (direct_workspace.cpp): a segment's force T = (EA C +
  // BA (C - C_0) / h) / L, C_0 its stretch at the step's start (from px), is lambda = T h^2 when C - s = alpha~
  // lambda, alpha~ = L / (EA h^2 + BA h) and s = BA / (h EA + BA) C_0: the undamped constraint about the
  // shifted length L + s, with its compliance L / (EA h^2) scaled by EA / (EA + BA / h). xpbd's constraints
  // are two-sided, so C_0 counts as it is. The spool segment stays undamped: the winch changes its rest
  // length before the step, which px's length does not know.
  const double rest = state.rest[j];
  if (j == state.first)
  {
    *stop = *alpha_len = rest;
    return;
  }
  const double ea = settings.axial_stiffness;
  *stop = rest + settings.dampingShiftShare() * (state.startLength(j) - rest);
  *alpha_len = rest * (ea / (ea + settings.axial_damping / settings.time_step));
}

void PbdSolver::copyIn(Cable& state, std::size_t m)
{
  const std::size_t f = state.first;
  // Masses, rest lengths and weights change only near the spool (pay-out) or on a rebuild: copy them
  // again only for the particles the state marks dirty, or all when the layout shifted.
  std::size_t begin = 0;
  std::size_t end = m;
  if (f == copied_first_ && state.size() == copied_size_ && copied_block_ == block_)
  {
    begin = state.dirty_begin > f ? state.dirty_begin - f : 0;
    end = state.dirty_end > f ? std::min(state.dirty_end - f, m) : 0;
  }
  for (std::size_t l = begin; l < end; ++l)
  {
    const std::size_t s = slot(l);
    inv_mass_[s] = state.inv_mass[f + l];
    if (l + 1 < m)
    {
      rest_[s] = state.rest[f + l];
      weight_[s] = state.stretch_weight[f + l];
    }
    if (l + 2 < m)
    {
      bend_rest_[s] = state.bend_rest[f + l];
      bend_weight_[s] = state.bend_weight[f + l];
    }
  }
  state.dirty_begin = state.dirty_end = 0;
  copied_first_ = f;
  copied_size_ = state.size();
  copied_block_ = block_;
  for (std::size_t l = 0; l < m; ++l)
  {
    const std::size_t s = slot(l);
    x_[s] = state.x[f + l];
    y_[s] = state.y[f + l];
    z_[s] = state.z[f + l];
    lambda_[s] = 0.0;
    bend_lambda_[s] = 0.0;
    joint_x_[s] = joint_y_[s] = joint_z_[s] = 0.0;
  }
}

void PbdSolver::copyOut(Cable& state, Multipliers& lambda, std::size_t m, bool bending) const
{
  const std::size_t f = state.first;
  for (std::size_t l = 0; l < m; ++l)
  {
    const std::size_t s = slot(l);
    state.x[f + l] = x_[s];
    state.y[f + l] = y_[s];
    state.z[f + l] = z_[s];
  }
  resetMultipliers(state, lambda, state.size() - 1, state.size() >= f + 3 ? state.size() - 2 : f);
  for (std::size_t l = 0; l + 1 < m; ++l)
  {
    lambda.stretch[f + l] = lambda_[slot(l)];
  }
  if (bending)
  {
    for (std::size_t l = 0; l + 2 < m; ++l)
    {
      lambda.bend[f + l] = bend_lambda_[slot(l)];
    }
  }
}

namespace
{

/// Projects the constraints j = first, first + step, ... below end (each joins j and j + span) of the
/// state's own arrays. The constraints of one call share no particle, so their order does not matter.
template <int kPower>
void projectStrided(Cable& state, Multipliers& multipliers, std::size_t first, std::size_t end, std::size_t step,
                    std::size_t span, bool bend, double compliance, double relax, const double* stop = nullptr,
                    const double* alpha_len = nullptr)
{
  double* x = state.x.data();
  double* y = state.y.data();
  double* z = state.z.data();
  const double* w = state.inv_mass.data();
  const double* rest = bend ? state.bend_rest.data() : state.rest.data();
  const double* weight = bend ? state.bend_weight.data() : state.stretch_weight.data();
  double* lambda = bend ? multipliers.bend.data() : multipliers.stretch.data();
  for (std::size_t j = first; j < end; j += step)
  {
    if (state.anisotropic)
    {
      projectPairAnisotropic<kPower>(state, j, j + span, rest[j], lambda[j], compliance, relax,
                                     kPower == 1 ? stop[j] : 0.0, kPower == 1 ? alpha_len[j] : 0.0);
      continue;
    }
    projectPairs<kPower>(x + j, y + j, z + j, w + j, x + j + span, y + j + span, z + j + span, w + j + span, rest + j,
                         weight + j, lambda + j, 1, compliance, relax, kPower == 1 ? stop + j : nullptr,
                         kPower == 1 ? alpha_len + j : nullptr);
  }
}

/// xpbd's joints j = first, first + 4, ... below end of the state's own arrays (multipliers by deployed index).
void projectJointsStrided(Cable& state, std::size_t first, std::size_t end, double inv_ei_h2, double* mx, double* my,
                          double* mz)
{
  const std::size_t f = state.first;
  for (std::size_t j = first; j < end; j += 4)
  {
    const std::size_t l = j - f;
    if (state.anisotropic)
    {
      double mu[3] = {mx[l], my[l], mz[l]};
      projectJointAnisotropic(state, j, inv_ei_h2, mu);
      mx[l] = mu[0], my[l] = mu[1], mz[l] = mu[2];
      continue;
    }
    projectJoint(state.x[j], state.y[j], state.z[j], state.inv_mass[j], state.x[j + 1], state.y[j + 1], state.z[j + 1],
                 state.inv_mass[j + 1], state.x[j + 2], state.y[j + 2], state.z[j + 2], state.inv_mass[j + 2],
                 state.rest[j], state.rest[j + 1], mx[l], my[l], mz[l], inv_ei_h2);
  }
}

template <int kStretch>
void solveDirectImpl(Cable& state, Multipliers& lambda, int iterations, bool bending, double stretch_compliance,
                     double inv_ei_h2, double relax, double* mx, double* my, double* mz, const double* stop,
                     const double* alpha_len)
{
  const std::size_t f = state.first;
  const std::size_t segments_end = state.size() - 1;
  const std::size_t bends_end = state.size() >= f + 3 ? state.size() - 2 : f;
  for (int iteration = 0; iteration < iterations; ++iteration)
  {
    // The blocked solver's sets, merged where they are independent: all even segments, all odd ones,
    // then bending residues {0, 1} and {2, 3} (mod 4), or the joints' residues 0, 1, 2, 3 in turn. Same
    // projections, same order of dependent ones.
    projectStrided<kStretch>(state, lambda, f, segments_end, 2, 1, false, stretch_compliance, relax, stop, alpha_len);
    projectStrided<kStretch>(state, lambda, f + 1, segments_end, 2, 1, false, stretch_compliance, relax, stop,
                             alpha_len);
    if (bending)
    {
      for (std::size_t r : {0, 2})
      {
        projectStrided<0>(state, lambda, f + r, bends_end, 4, 2, true, 0.0, relax);
        projectStrided<0>(state, lambda, f + r + 1, bends_end, 4, 2, true, 0.0, relax);
      }
    }
    for (std::size_t r = 0; inv_ei_h2 > 0.0 && r < 4; ++r)
    {
      projectJointsStrided(state, f + r, bends_end, inv_ei_h2, mx, my, mz);
    }
  }
}

}  // namespace

void PbdSolver::solveDirect(Cable& state, Multipliers& lambda, int iterations, bool bending, double stretch_compliance,
                            double inv_ei_h2, double relax, const double* stop, const double* alpha_len)
{
  const std::size_t f = state.first;
  resetMultipliers(state, lambda, state.size() - 1, state.size() >= f + 3 ? state.size() - 2 : f);
  std::fill(joint_x_.begin(), joint_x_.end(), 0.0);
  std::fill(joint_y_.begin(), joint_y_.end(), 0.0);
  std::fill(joint_z_.begin(), joint_z_.end(), 0.0);
  if (stretch_compliance == 0.0)
  {
    solveDirectImpl<0>(state, lambda, iterations, bending, 0.0, 0.0, relax, nullptr, nullptr, nullptr, nullptr,
                       nullptr);
  }
  else
  {
    solveDirectImpl<1>(state, lambda, iterations, bending, stretch_compliance, inv_ei_h2, 1.0, joint_x_.data(),
                       joint_y_.data(), joint_z_.data(), stop, alpha_len);
  }
  state.dirty_begin = state.dirty_end = 0;
}

void SequentialPbdSolver::project(Cable& state, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t n = state.size();
  const std::size_t f = state.first;
  if (n < f + 2)
  {
    return;
  }
  const std::size_t segments_end = n - 1;
  const std::size_t bends_end = n >= f + 3 ? n - 2 : f;
  resetMultipliers(state, lambda, segments_end, bends_end);
  double* x = state.x.data();
  double* y = state.y.data();
  double* z = state.z.data();
  const double* w = state.inv_mass.data();
  for (int iteration = 0; iteration < settings.iterations; ++iteration)
  {
    for (std::size_t j = f; j < segments_end; ++j)
    {
      if (state.anisotropic)
      {
        projectPairAnisotropic<0>(state, j, j + 1, state.rest[j], lambda.stretch[j], 0.0, 1.0);
        continue;
      }
      projectPairs<0>(x + j, y + j, z + j, w + j, x + j + 1, y + j + 1, z + j + 1, w + j + 1, &state.rest[j],
                      &state.stretch_weight[j], &lambda.stretch[j], 1);
    }
    if (settings.bending)
    {
      for (std::size_t j = f; j < bends_end; ++j)
      {
        if (state.anisotropic)
        {
          projectPairAnisotropic<0>(state, j, j + 2, state.bend_rest[j], lambda.bend[j], 0.0, 1.0);
          continue;
        }
        projectPairs<0>(x + j, y + j, z + j, w + j, x + j + 2, y + j + 2, z + j + 2, w + j + 2, &state.bend_rest[j],
                        &state.bend_weight[j], &lambda.bend[j], 1);
      }
    }
  }
}

}  // namespace rov_tether
