// The direct solver's primal path (direct_primal.hpp): the step energy's gradient and Hessian, assembled by
// 3x3 blocks of particles (mass, segments' axial and geometric stiffness, the bending joints), and what stays
// the same through a step's Newton iterations. The Newton iteration itself is in direct_primal.cpp.
#include <algorithm>
#include <limits>

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

/// bendingRows, compiled for each instruction set.
ROV_TETHER_TARGET_CLONES void bendingRowsCloned(const BendingRows& io, std::size_t from, std::size_t to)
{
  const double* __restrict w = io.w, * __restrict ir = io.inv_rest, * __restrict ig = io.inv_gamma;
  double* __restrict p0 = io.pull[0], * __restrict p1 = io.pull[1], * __restrict p2 = io.pull[2];
  double* __restrict diag = io.diag;
  double* __restrict f0 = io.first[0], * __restrict f1 = io.first[1], * __restrict second = io.second;
#pragma omp simd
  for (std::size_t l = from; l < to; ++l)
  {
    const bool free_l = w[l] != 0.0;
    // The inverse rest lengths of the segments before particle l, after it and after that: particle l is weight
    // 2 (b = before) of joint l - 2, weight 1 (-(a + b) = -(before + own)) of joint l - 1, weight 0 (a = own) of
    // joint l, whose weight 2 is after.
    const double before = ir[l - 1], own = ir[l], after = ir[l + 1];
    const double w2 = before, w1 = -(before + own), w0 = own;
    const double inv2 = ig[l - 2], inv1 = ig[l - 1], inv0 = ig[l];
    const double gr2 = free_l ? w2 : 0.0, gr1 = free_l ? w1 : 0.0, gr0 = free_l ? w0 : 0.0;
    const double v2 = free_l ? inv2 : 0.0, v1 = free_l ? inv1 : 0.0, v0 = free_l ? inv0 : 0.0;
    p0[l] = gr2 * v2, p1[l] = gr1 * v1, p2[l] = gr0 * v0;
    diag[l] = gr2 * gr2 * v2 + gr1 * gr1 * v1 + gr0 * gr0 * v0;
    // The block (l + 1, l): joint l - 1 (particle l its weight 1, l + 1 its weight 2), joint l (0 and 1).
    const bool pair = free_l && w[l + 1] != 0.0;
    const double first1 = own * w1 * inv1;              // joint l - 1's weights 2 and 1
    const double first0 = -(own + after) * own * inv0;  // joint l's weights 1 and 0
    f0[l] = pair ? first1 : 0.0;
    f1[l] = pair ? first0 : 0.0;
    const double coupling = after * own * inv0;  // joint l: particle l its weight 0, l + 2 its weight 2
    second[l] = free_l && w[l + 2] != 0.0 ? coupling : 0.0;
  }
}

/// What segmentTerms reads: each segment's stretch, law and geometry, and its particles' inverse masses.
struct SegmentInputs
{
  const double *c, *alpha, *stiffness, *dashpot, *middle, *kink, *model, *lambda, *len, *w, *w_along, *nx, *ny, *nz;
  /// The most a compressed segment's geometric stiffness may take off either end's mass (infinity: all of it).
  double compressed_share;
};
/// segmentTerms' results, segment k at entry k + 1 (entries 0 and m + 1 stay 0: no segment before the first
/// particle nor after the last): in the model (1 or 0), its force, its block's scale and geometric stiffness, n.
struct SegmentTerms
{
  double *on, *lam, *scale, *geometric, *nx, *ny, *nz;
};

/// Each of `count` segments' Hessian block (axial - geometric) n n^T + geometric I as its scale and geometric
/// stiffness, and its force in the gradient, and whether it is in the model: the segments of the model are
/// all of a rod's; of a cable's, those the step stretches (solveModel), or on their law's middle piece (a
/// slack segment's dashpot: its force and slope). `along`: the cable's added mass makes it anisotropic
/// (w_along). The drum's spool segment is set by the caller. kUnilateral false: a rod's, every segment in the
/// model and none on a middle piece (the selects below, with their loads, left out).
template <bool kUnilateral>
ROV_TETHER_TARGET_CLONES void segmentTerms(const SegmentInputs& in, const SegmentTerms& out, std::size_t count,
                                           bool along)
{
  // Every value is computed and the law's pieces selected, with no branch, so that the loop vectorises; the
  // pointers are copied out of the structs, which the stores could otherwise alias.
  const double* __restrict c = in.c, * __restrict alpha = in.alpha, * __restrict stiffness = in.stiffness;
  const double* __restrict dashpot = in.dashpot, * __restrict middle = in.middle, * __restrict kink = in.kink;
  const double* __restrict model = in.model, * __restrict lambda = in.lambda, * __restrict len = in.len;
  const double* __restrict w = in.w, * __restrict w_along = along ? in.w_along : in.w;
  const double* __restrict nx = in.nx, * __restrict ny = in.ny, * __restrict nz = in.nz;
  const double share = in.compressed_share;
  double* __restrict on = out.on + 1, * __restrict lam = out.lam + 1, * __restrict scale = out.scale + 1;
  double* __restrict geometric = out.geometric + 1;
  double* __restrict ox = out.nx + 1, * __restrict oy = out.ny + 1, * __restrict oz = out.nz + 1;
#pragma omp simd
  for (std::size_t k = 0; k < count; ++k)
  {
    // Every load unconditional (a load behind && could trap, which keeps the loop from vectorising).
    const double slope = dashpot[k], piece = middle[k], wa = w[k], wb = w[k + 1], va = w_along[k], vb = w_along[k + 1];
    const bool in_middle = kUnilateral && (slope > 0.0) & (piece > 0.0);
    const double middle_force = kink[k] / alpha[k] + slope * (c[k] - kink[k]);
    const double taut_force = c[k] / alpha[k];
    // Hessian of the segment's energy: axial (1 / alpha) n n^T plus the geometric stiffness
    // lambda / |d| (I - n n^T) of the Newton estimate of lambda (not C / alpha, which a stiff segment's
    // rounding makes useless). In compression it is negative: kept whole (the exact Hessian; where that is
    // not definite, a rod buckling, solveModel shifts it by a multiple of the masses), or, once even the
    // largest shift was not definite, kept while it is at most kCompressedShare of the mass of either end
    // (then each particle's two segments take at most half its mass off the Hessian's smallest eigenvalue,
    // which stays positive) and dropped beyond. Dropped always, a cable lying slack on a seabed converged
    // linearly: 4 iterations a step instead of 2; dropped beyond the eighth, a rod pushed into buckling did.
    const double quotient = lambda[k] / (len[k] > 0.0 ? len[k] : 1.0);
    const double g = len[k] > 0.0 ? quotient : 0.0;
    // A particle's largest inverse mass (along the cable, where added mass does not act).
    const double mobility = std::max(std::max(wa, va), std::max(wb, vb));
    const double kept = g < 0.0 && !(-g * mobility <= share) ? 0.0 : g;
    on[k] = !kUnilateral || in_middle || model[k] > 0.0 ? 1.0 : 0.0;
    lam[k] = in_middle ? middle_force : taut_force;
    scale[k] = (in_middle ? slope : stiffness[k]) - kept;
    geometric[k] = kept;
    ox[k] = nx[k], oy[k] = ny[k], oz[k] = nz[k];
  }
}

/// What the rows' assembly reads, by particle l of the deployed ones: its inverse mass (0 pinned), mass and extra
/// mass along the cable, position and prediction, tangent (with added mass), segmentTerms' terms (segment l - 1 at
/// entry l, segment l at l + 1) and prepareBending's (each of a row's three joints' its own array, the
/// curvatures offset by 2: joint l - 2 + i at entry l + i).
struct RowInputs
{
  PrimalNewton::Particles p;
  SegmentTerms segment;
  const double *bend_diag, *bend_pull[3], *bend_first[2], *cx, *cy, *cz;
};

/// A diagonal block and its row of the gradient, as named numbers (arrays in the rows' loop kept it from
/// vectorising).
struct RowSums
{
  double b0, b1, b2, b3, b4, b5, b6, b7, b8, g0, g1, g2;
};

/// Adds a segment's block scale n n^T + geometric I to the diagonal block and its force f n to the gradient.
/// kAllOn: the segment is in the model (a rod's always are); else it is added when `on` is 1, and selected out,
/// not added as 0, when not (the same roundings as not adding it).
template <bool kAllOn>
ROV_TETHER_INLINE void addSegment(double on, double a, double q, double n0, double n1, double n2, double f, RowSums& r)
{
  const bool in_model = kAllOn || on > 0.0;
  r.b0 = in_model ? r.b0 + (a * n0 * n0 + q) : r.b0;
  r.b1 = in_model ? r.b1 + (a * n0 * n1 + 0.0) : r.b1;
  r.b2 = in_model ? r.b2 + (a * n0 * n2 + 0.0) : r.b2;
  r.b3 = in_model ? r.b3 + (a * n1 * n0 + 0.0) : r.b3;
  r.b4 = in_model ? r.b4 + (a * n1 * n1 + q) : r.b4;
  r.b5 = in_model ? r.b5 + (a * n1 * n2 + 0.0) : r.b5;
  r.b6 = in_model ? r.b6 + (a * n2 * n0 + 0.0) : r.b6;
  r.b7 = in_model ? r.b7 + (a * n2 * n1 + 0.0) : r.b7;
  r.b8 = in_model ? r.b8 + (a * n2 * n2 + q) : r.b8;
  r.g0 = in_model ? r.g0 + f * n0 : r.g0;
  r.g1 = in_model ? r.g1 + f * n1 : r.g1;
  r.g2 = in_model ? r.g2 + f * n2 : r.g2;
}

/// The Hessian's diagonal blocks and the gradient of rows [0, rows), a row at a time, written whole (no
/// clearing pass), each entry's terms added in a fixed order: the mass, segment l - 1, segment l, then the
/// bending joints l - 2, l - 1, l. A pinned particle's row is the identity. Branch-free within a row, so
/// that the rows vectorise. With bending (a rod) every segment is in the model, and rows 0 and m add the empty
/// entries before the first segment and after the last as well: exact zeros, which change at most the sign of a
/// zero in the gradient (-0.0 + 0.0 is 0.0), which no sum with a nonzero number sees.
template <bool kAlong, bool kBending>
ROV_TETHER_TARGET_CLONES void assembleRows(const RowInputs& in, double* __restrict diag, double* __restrict grad,
                                           std::size_t rows, std::size_t stride)
{
  const double* __restrict w = in.p.w, * __restrict mass = in.p.mass, * __restrict less = in.p.less;
  const double* __restrict x = in.p.x, * __restrict y = in.p.y, * __restrict z = in.p.z;
  const double* __restrict xt = in.p.xt, * __restrict yt = in.p.yt, * __restrict zt = in.p.zt;
  const double* __restrict tx = in.p.tx, * __restrict ty = in.p.ty, * __restrict tz = in.p.tz;
  const double* __restrict on = in.segment.on, * __restrict lam = in.segment.lam;
  const double* __restrict scale = in.segment.scale, * __restrict geometric = in.segment.geometric;
  const double* __restrict nx = in.segment.nx, * __restrict ny = in.segment.ny, * __restrict nz = in.segment.nz;
#pragma omp simd
  for (std::size_t l = 0; l < rows; ++l)
  {
    const double m = mass[l];
    const double d0 = x[l] - xt[l], d1 = y[l] - yt[l], d2 = z[l] - zt[l];
    RowSums r{m, 0.0, 0.0, 0.0, m, 0.0, 0.0, 0.0, m, 0.0, 0.0, 0.0};
    if (kAlong)
    {
      // The particle's mass matrix: m_across I, plus (m_along - m_across) t t^T.
      const double t0 = tx[l], t1 = ty[l], t2 = tz[l];
      const double e = less[l];
      r.b0 += e * t0 * t0, r.b1 += e * t0 * t1, r.b2 += e * t0 * t2;
      r.b3 += e * t1 * t0, r.b4 += e * t1 * t1, r.b5 += e * t1 * t2;
      r.b6 += e * t2 * t0, r.b7 += e * t2 * t1, r.b8 += e * t2 * t2;
      r.g0 = r.b0 * d0 + r.b1 * d1 + r.b2 * d2;
      r.g1 = r.b3 * d0 + r.b4 * d1 + r.b5 * d2;
      r.g2 = r.b6 * d0 + r.b7 * d1 + r.b8 * d2;
    }
    else
    {
      r.g0 = m * d0, r.g1 = m * d1, r.g2 = m * d2;
    }
    // Segment l - 1 (entry l; dC/dx_l = +n) and segment l (entry l + 1; -n): the gradient gets J^T lambda.
    addSegment<kBending>(on[l], scale[l], geometric[l], nx[l], ny[l], nz[l], lam[l], r);
    addSegment<kBending>(on[l + 1], scale[l + 1], geometric[l + 1], nx[l + 1], ny[l + 1], nz[l + 1], -lam[l + 1], r);
    const bool pinned = w[l] == 0.0;
    // One array an entry (banded::BlockLayout{1, stride}): a block a row would be 9 stores apart, which
    // keeps the loop from vectorising. Only the lower triangle: the block solves read no other (entries 1, 2
    // and 5 stay 0, as reserve left them, and the segments' terms of them are not computed). With bending, the
    // entries the joints add to (0, 4, 8 and the gradient) are left as they are for bendingRowsAdded.
    double* out = diag + l;
    out[3 * stride] = pinned ? 0.0 : r.b3;
    out[6 * stride] = pinned ? 0.0 : r.b6, out[7 * stride] = pinned ? 0.0 : r.b7;
    out[0] = pinned && !kBending ? 1.0 : r.b0;
    out[4 * stride] = pinned && !kBending ? 1.0 : r.b4, out[8 * stride] = pinned && !kBending ? 1.0 : r.b8;
    grad[l] = pinned && !kBending ? 0.0 : r.g0;
    grad[stride + l] = pinned && !kBending ? 0.0 : r.g1;
    grad[2 * stride + l] = pinned && !kBending ? 0.0 : r.g2;
  }
}

/// The bending joints' terms of rows [0, rows), after assembleRows<kAlong, true>: each row's joints l - 2, l - 1,
/// l, their diagonal terms' sum, then their pulls in that order (the curvatures' entry l + i is joint l - 2 + i),
/// added to what assembleRows left there, and a pinned particle's row made the identity's. A loop of its own:
/// the rows' one loop had more arrays than the processor has registers for their addresses.
ROV_TETHER_TARGET_CLONES void bendingRowsAdded(const RowInputs& in, double* __restrict diag, double* __restrict grad,
                                               std::size_t rows, std::size_t stride)
{
  const double* __restrict w = in.p.w;
  const double* __restrict bend = in.bend_diag, * __restrict p0 = in.bend_pull[0];
  const double* __restrict p1 = in.bend_pull[1], * __restrict p2 = in.bend_pull[2];
  const double* __restrict cx = in.cx, * __restrict cy = in.cy, * __restrict cz = in.cz;
  double* __restrict d0 = diag, * __restrict d4 = diag + 4 * stride, * __restrict d8 = diag + 8 * stride;
  double* __restrict g0 = grad, * __restrict g1 = grad + stride, * __restrict g2 = grad + 2 * stride;
#pragma omp simd
  for (std::size_t l = 0; l < rows; ++l)
  {
    double b0 = d0[l], b4 = d4[l], b8 = d8[l], r0 = g0[l], r1 = g1[l], r2 = g2[l];
    b0 += bend[l], b4 += bend[l], b8 += bend[l];
    addJointPulls(p0, p1, p2, cx, cy, cz, l, r0, r1, r2);
    const bool pinned = w[l] == 0.0;
    d0[l] = pinned ? 1.0 : b0, d4[l] = pinned ? 1.0 : b4, d8[l] = pinned ? 1.0 : b8;
    g0[l] = pinned ? 0.0 : r0, g1[l] = pinned ? 0.0 : r1, g2[l] = pinned ? 0.0 : r2;
  }
}

/// The Hessian's first blocks below the diagonal, (l + 1, l) for l < rows: segment l's block, negated, where it
/// couples two free particles, plus the bending joints' terms of a free particle l.
template <bool kBending>
ROV_TETHER_TARGET_CLONES void assembleBelow(const RowInputs& in, double* __restrict below, std::size_t rows,
                                            std::size_t stride)
{
  const double* __restrict w = in.p.w;
  const double* __restrict on = in.segment.on + 1, * __restrict scale = in.segment.scale + 1;
  const double* __restrict geometric = in.segment.geometric + 1;
  const double* __restrict nx = in.segment.nx + 1, * __restrict ny = in.segment.ny + 1;
  const double* __restrict nz = in.segment.nz + 1;
  const double* __restrict u0 = in.bend_first[0], * __restrict u1 = in.bend_first[1];
#pragma omp simd
  for (std::size_t l = 0; l < rows; ++l)
  {
    // Segment l (entry l + 1 of segmentTerms', l of these pointers).
    const bool free = w[l] != 0.0;
    const bool coupled = (on[l] > 0.0) & free & (w[l + 1] != 0.0);
    const double a = scale[l], q = geometric[l], n0 = nx[l], n1 = ny[l], n2 = nz[l];
    RowSums r{0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    addSegment<true>(1.0, a, q, n0, n1, n2, 0.0, r);  // 0.0 + entry: the entry (0.0 + -0.0 is 0.0, negated below)
    // The block negated where the segment couples two free particles: 0.0 + -1.0 entry.
    const double block[9] = {0.0 + -1.0 * r.b0, 0.0 + -1.0 * r.b1, 0.0 + -1.0 * r.b2,
                             0.0 + -1.0 * r.b3, 0.0 + -1.0 * r.b4, 0.0 + -1.0 * r.b5,
                             0.0 + -1.0 * r.b6, 0.0 + -1.0 * r.b7, 0.0 + -1.0 * r.b8};
    double e0 = coupled ? block[0] : 0.0, e4 = coupled ? block[4] : 0.0, e8 = coupled ? block[8] : 0.0;
    if (kBending)
    {
      e0 = free ? e0 + u0[l] : e0, e4 = free ? e4 + u0[l] : e4, e8 = free ? e8 + u0[l] : e8;
      e0 = free ? e0 + u1[l] : e0, e4 = free ? e4 + u1[l] : e4, e8 = free ? e8 + u1[l] : e8;
    }
    below[l] = e0, below[4 * stride + l] = e4, below[8 * stride + l] = e8;
    below[stride + l] = coupled ? block[1] : 0.0, below[2 * stride + l] = coupled ? block[2] : 0.0;
    below[3 * stride + l] = coupled ? block[3] : 0.0, below[5 * stride + l] = coupled ? block[5] : 0.0;
    below[6 * stride + l] = coupled ? block[6] : 0.0, below[7 * stride + l] = coupled ? block[7] : 0.0;
  }
}

}  // namespace

PrimalNewton::Particles PrimalNewton::particles(const Cable& cable) const
{
  const std::size_t f = ws_.first;
  const bool along = cable.anisotropic;
  return {cable.inv_mass.data() + f,
          mass_.data(),
          mass_less_.data(),
          cable.x.data() + f,
          cable.y.data() + f,
          cable.z.data() + f,
          ws_.xt.data(),
          ws_.yt.data(),
          ws_.zt.data(),
          along ? cable.tx.data() + f : nullptr,
          along ? cable.ty.data() + f : nullptr,
          along ? cable.tz.data() + f : nullptr};
}

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
    for (auto* curve : {&curve_x_, &curve_y_, &curve_z_})
    {
      // Joints m - 1 and m do not exist: 0 (a reel-in that merged a segment would have left them its last values).
      (*curve)[ws_.m + 1] = (*curve)[ws_.m + 2] = 0.0;
    }
  }
}

void PrimalNewton::assemble(const Cable& cable, bool whole_compression)
{
  // The Hessian by 3x3 blocks of particles: diagonal (l, l), first below (l + 1, l), second below (l + 2, l,
  // with bending: a multiple of the identity, prepareBending's). First each segment's terms, then the rows.
  const std::size_t f = ws_.first;
  const std::size_t m = ws_.m;
  const std::size_t stride = lambda_.size();
  const bool along = cable.anisotropic;
  const double* w = cable.inv_mass.data() + f;
  const SegmentTerms terms{segmentArray(0), segmentArray(1), segmentArray(2), segmentArray(3),
                           segmentArray(4), segmentArray(5), segmentArray(6)};
  const SegmentInputs in{ws_.c.data(),
                         ws_.alpha.data(),
                         stiffness_.data(),
                         ws_.dashpot.data(),
                         middle_.data(),
                         ws_.kink.data(),
                         ws_.on(),
                         lambda_.data(),
                         ws_.len.data(),
                         w,
                         along ? cable.inv_mass_along.data() + f : w,
                         ws_.nx.data(),
                         ws_.ny.data(),
                         ws_.nz.data(),
                         whole_compression ? std::numeric_limits<double>::infinity() : kCompressedShare};
  ws_.unilateral ? segmentTerms<true>(in, terms, m, along) : segmentTerms<false>(in, terms, m, along);
  for (double* v : {terms.on, terms.lam, terms.scale, terms.geometric, terms.nx, terms.ny, terms.nz})
  {
    v[0] = v[m + 1] = 0.0;  // no segment before the first particle nor after the last
  }
  if (ws_.drum != nullptr)
  {
    // The spool segment's force is the drum's law, solved for in solveModel: here only its geometric
    // stiffness.
    terms.on[1] = 1.0;
    terms.lam[1] = 0.0;
    terms.scale[1] = 0.0 - terms.geometric[1];
  }
  RowInputs rows{particles(cable),
                 terms,
                 bend_diag_.data(),
                 {term(bend_pull_, 0), term(bend_pull_, 1), term(bend_pull_, 2)},
                 {term(bend_first_, 0), term(bend_first_, 1)},
                 curve_x_.data(),
                 curve_y_.data(),
                 curve_z_.data()};
  double* gradient = grad_step_.data();  // by axis, one array each; free here (drumStep refills it before use)
  if (ws_.bending)
  {
    along ? assembleRows<true, true>(rows, hessian_diag_.data(), gradient, m + 1, stride)
          : assembleRows<false, true>(rows, hessian_diag_.data(), gradient, m + 1, stride);
    bendingRowsAdded(rows, hessian_diag_.data(), gradient, m + 1, stride);
    assembleBelow<true>(rows, hessian_first_.data(), m, stride);
  }
  else
  {
    along ? assembleRows<true, false>(rows, hessian_diag_.data(), gradient, m + 1, stride)
          : assembleRows<false, false>(rows, hessian_diag_.data(), gradient, m + 1, stride);
    assembleBelow<false>(rows, hessian_first_.data(), m, stride);
  }
  for (std::size_t l = 0; l <= m; ++l)
  {
    grad_[3 * l] = gradient[l], grad_[3 * l + 1] = gradient[stride + l], grad_[3 * l + 2] = gradient[2 * stride + l];
  }
}

void bendingRows(const BendingRows& rows, std::size_t from, std::size_t to) { bendingRowsCloned(rows, from, to); }

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
  // The rows with all three joints and two particles after them vectorised (bendingRows); the rest here.
  auto row = [&](std::size_t l)
  {
    const bool free_l = w[l] != 0.0;
    double diag[3];
    for (std::size_t i = 0; i < 3; ++i)
    {
      const std::size_t r = 2 - i;
      const bool on = free_l && joint(l, r);
      const double gr = on ? weight(l - r, r) : 0.0;
      const double inv = on ? ws_.inv_gamma[l - r] : 0.0;
      term(bend_pull_, i)[l] = gr * inv;  // each of a row's terms has its own array
      diag[i] = gr * gr * inv;
    }
    bend_diag_[l] = diag[0] + diag[1] + diag[2];
    const bool pair = l + 1 <= m && free_l && w[l + 1] != 0.0;  // the block (l + 1, l) couples two free ones
    for (std::size_t i = 0; i < 2; ++i)
    {
      const std::size_t s = 1 - i;
      term(bend_first_, i)[l] =
          pair && joint(l, s) ? weight(l - s, s + 1) * weight(l - s, s) * ws_.inv_gamma[l - s] : 0.0;
    }
    if (l + 2 <= m)
    {
      hessian_second_[l] =
          l + 1 < m && free_l && w[l + 2] != 0.0 ? weight(l, 2) * weight(l, 0) * ws_.inv_gamma[l] : 0.0;
    }
  };
  const std::size_t from = 2, to = m >= 3 ? m - 1 : from;  // rows 2 to m - 2
  const BendingRows rows{w,
                         ws_.inv_rest.data(),
                         ws_.inv_gamma.data(),
                         {term(bend_pull_, 0), term(bend_pull_, 1), term(bend_pull_, 2)},
                         bend_diag_.data(),
                         {term(bend_first_, 0), term(bend_first_, 1)},
                         hessian_second_.data()};
  bendingRows(rows, from, to);
  for (std::size_t l = 0; l < std::min(from, m + 1); ++l)
  {
    row(l);
  }
  for (std::size_t l = to; l <= m; ++l)
  {
    row(l);
  }
}

}  // namespace rov_tether
