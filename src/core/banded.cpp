#include "banded.hpp"

#include <lapacke.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "simd.hpp"

namespace rov_tether::banded
{

namespace
{

/// Rows between rescalings of the leading minors (they grow or shrink geometrically).
constexpr std::size_t kRescale = 8;

/// 2^-k for the binary exponent k of v: multiplying by it is exact and brings |v| into [1, 2). Read off
/// the bits (no library call in the loop); 1 for zero, subnormal, infinite or NaN v.
inline double unitScale(double v)
{
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const std::uint64_t biased = (bits >> 52) & 0x7ff;
  if (biased == 0 || biased >= 2046)
  {
    return 1.0;
  }
  const std::uint64_t scale_bits = (2046 - biased) << 52;
  double scale;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  return scale;
}

/// u_i = b_i / d_i and v_i = e_i / d_i for rows [0, count) (no dependency between rows: vectorised);
/// false when a pivot is not positive.
ROV_TETHER_TARGET_CLONES bool reciprocals(const double* __restrict d, double* __restrict e, double* __restrict b,
                                          std::size_t count)
{
  double smallest = 1.0;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double r = 1.0 / d[i];
    b[i] *= r;
    e[i] *= r;
    smallest = d[i] < smallest ? d[i] : smallest;
  }
  return smallest > 0.0;
}

}  // namespace

bool solveTridiagonalSweep(double* d, double* e, double* b, std::size_t n)
{
  // A twisted L D L^T without divisions in its recurrences: eliminating from the top, the pivots are
  // d_i = P_i / P_i-1 with the leading minors P_i = a_i P_i-1 - e_i-1^2 P_i-2, and the forward substitution
  // is Y_i = P_i-1 b_i - e_i-1 Y_i-1 (Y_i = P_i-1 y_i); from the bottom the same with the trailing minors.
  // Each recurrence step is one fused multiply-add, the two ends run at once and meet at row p, and the
  // divisions (one reciprocal a row) come afterwards in a loop without dependencies. The minors are rescaled
  // by powers of two every kRescale rows, which is exact. Row i < p keeps x_i = u_i - v_i x_i+1 with
  // u_i = Y_i / P_i and v_i = e_i P_i-1 / P_i (in d, b and e); row i > p the mirror image.
  if (n == 0)
  {
    return true;
  }
  if (n == 1)
  {
    if (!(d[0] > 0.0))
    {
      return false;
    }
    b[0] /= d[0];
    return true;
  }
  const std::size_t p = n / 2;
  // Top: rows 0 .. p-1. State: P_i-1 (pm1), P_i-2 (pm2), Y_i-1 (y), original e_i-1 (ep).
  double pm2 = 0.0, pm1 = 1.0, y = 0.0, ep = 0.0;
  // Bottom: rows n-1 .. p+1. State: Q_i+1 (qm1), Q_i+2 (qm2), Z_i+1 (z), original e_i (eq).
  double qm2 = 0.0, qm1 = 1.0, z = 0.0, eq = 0.0;
  const std::size_t down = p;
  const std::size_t up = n - 1 - p;
  for (std::size_t s = 0; s < down || s < up; ++s)
  {
    if (s < down)
    {
      const std::size_t i = s;
      const double pi = d[i] * pm1 - ep * ep * pm2;
      const double yi = pm1 * b[i] - ep * y;
      const double ei = e[i];
      d[i] = pi, b[i] = yi, e[i] = ei * pm1;
      pm2 = pm1, pm1 = pi, y = yi, ep = ei;
      if ((s + 1) % kRescale == 0)
      {
        const double scale = unitScale(pm1);
        pm1 *= scale, pm2 *= scale, y *= scale;
      }
    }
    if (s < up)
    {
      const std::size_t i = n - 1 - s;
      const double qi = d[i] * qm1 - eq * eq * qm2;
      const double zi = qm1 * b[i] - eq * z;
      const double ei = e[i - 1];
      d[i] = qi, b[i] = zi, e[i - 1] = ei * qm1;
      qm2 = qm1, qm1 = qi, z = zi, eq = ei;
      if ((s + 1) % kRescale == 0)
      {
        const double scale = unitScale(qm1);
        qm1 *= scale, qm2 *= scale, z *= scale;
      }
    }
  }
  // Row p: a_p x_p + e_p-1 x_p-1 + e_p x_p+1 = b_p with x_p-1 and x_p+1 from the two ends.
  // pm1 = P_p-1, pm2 = P_p-2, y = Y_p-1 (ep = e_p-1); qm1 = Q_p+1, qm2 = Q_p+2, z = Z_p+1 (eq = e_p).
  const double pivot = d[p] - (p > 0 ? ep * ep * pm2 / pm1 : 0.0) - (up > 0 ? eq * eq * qm2 / qm1 : 0.0);
  const double right = b[p] - (p > 0 ? ep * y / pm1 : 0.0) - (up > 0 ? eq * z / qm1 : 0.0);
  if (!(pivot > 0.0))
  {
    return false;
  }
  if (!reciprocals(d, e, b, p) || !reciprocals(d + p + 1, e + p, b + p + 1, up))
  {
    return false;
  }
  b[p] = right / pivot;
  double above = b[p];  // x_i+1 going up, x_i-1 going down: kept in registers, not reloaded
  double below = b[p];
  for (std::size_t s = 1; s <= down || s <= up; ++s)
  {
    if (s <= down)
    {
      const std::size_t i = p - s;
      above = b[i] - e[i] * above;
      b[i] = above;
    }
    if (s <= up)
    {
      const std::size_t i = p + s;
      below = b[i] - e[i - 1] * below;
      b[i] = below;
    }
  }
  return true;
}

bool solveTridiagonalLapack(double* d, double* e, double* b, std::size_t n)
{
  const auto size = static_cast<lapack_int>(n);
  if (LAPACKE_dpttrf(size, d, e) != 0)
  {
    return false;
  }
  return LAPACKE_dpttrs(LAPACK_COL_MAJOR, size, 1, d, e, b, size) == 0;
}

namespace
{

/// L D L^T of an SPD band with the half-bandwidth kKd known at compile time, so each column's update is a
/// fixed, unrolled set of independent multiply-adds; no square roots, one reciprocal a column. The band
/// (LAPACK's lower layout) is overwritten with L below the diagonal and D on it; b with the solution.
template <std::size_t kKd>
bool bandLdlt(double* __restrict ab, double* __restrict b, std::size_t n)
{
  constexpr std::size_t ld = kKd + 1;
  for (std::size_t j = 0; j < n; ++j)
  {
    double* column = ab + j * ld;
    const double pivot = column[0];
    if (!(pivot > 0.0))
    {
      return false;
    }
    const double inverse = 1.0 / pivot;
    const std::size_t below = std::min(kKd, n - 1 - j);
    double l[kKd];
    for (std::size_t r = 1; r <= kKd; ++r)
    {
      l[r - 1] = r <= below ? column[r] * inverse : 0.0;
    }
    // A(j + r, j + q) -= l_r pivot l_q for 1 <= q <= r <= below: column j + q holds row j + r at r - q.
    for (std::size_t q = 1; q <= kKd; ++q)
    {
      if (q > below)
      {
        break;
      }
      double* target = ab + (j + q) * ld;
      const double scaled = l[q - 1] * pivot;
      for (std::size_t r = q; r <= kKd; ++r)
      {
        target[r - q] -= l[r - 1] * scaled;
      }
    }
    for (std::size_t r = 1; r <= below; ++r)
    {
      column[r] = l[r - 1];
    }
  }
  // L y = b, D z = y, L^T x = z.
  for (std::size_t j = 0; j < n; ++j)
  {
    const double* column = ab + j * ld;
    const double value = b[j];
    const std::size_t below = std::min(kKd, n - 1 - j);
    for (std::size_t r = 1; r <= below; ++r)
    {
      b[j + r] -= column[r] * value;
    }
  }
  for (std::size_t j = n; j-- > 0;)
  {
    const double* column = ab + j * ld;
    double value = b[j] / column[0];
    const std::size_t below = std::min(kKd, n - 1 - j);
    for (std::size_t r = 1; r <= below; ++r)
    {
      value -= column[r] * b[j + r];
    }
    b[j] = value;
  }
  return true;
}

/// The same for any half-bandwidth (columns of the band updated in loops).
bool bandLdltAny(double* ab, std::size_t kd, double* b, std::size_t n)
{
  const std::size_t ld = kd + 1;
  for (std::size_t j = 0; j < n; ++j)
  {
    double* column = ab + j * ld;
    const double pivot = column[0];
    if (!(pivot > 0.0))
    {
      return false;
    }
    const std::size_t below = std::min(kd, n - 1 - j);
    for (std::size_t r = 1; r <= below; ++r)
    {
      column[r] /= pivot;
    }
    for (std::size_t q = 1; q <= below; ++q)
    {
      double* target = ab + (j + q) * ld;
      const double scaled = column[q] * pivot;
      for (std::size_t r = q; r <= below; ++r)
      {
        target[r - q] -= column[r] * scaled;
      }
    }
  }
  for (std::size_t j = 0; j < n; ++j)
  {
    const double* column = ab + j * ld;
    const std::size_t below = std::min(kd, n - 1 - j);
    for (std::size_t r = 1; r <= below; ++r)
    {
      b[j + r] -= column[r] * b[j];
    }
  }
  for (std::size_t j = n; j-- > 0;)
  {
    const double* column = ab + j * ld;
    double value = b[j] / column[0];
    const std::size_t below = std::min(kd, n - 1 - j);
    for (std::size_t r = 1; r <= below; ++r)
    {
      value -= column[r] * b[j + r];
    }
    b[j] = value;
  }
  return true;
}

}  // namespace

bool solveBandedSweep(double* ab, std::size_t kd, double* b, std::size_t n)
{
  switch (kd)
  {
    case 5:
      return bandLdlt<5>(ab, b, n);
    case 8:
      return bandLdlt<8>(ab, b, n);
    case 10:
      return bandLdlt<10>(ab, b, n);
    default:
      return bandLdltAny(ab, kd, b, n);
  }
}

bool solveBandedLapack(double* ab, std::size_t kd, double* b, std::size_t n)
{
  const auto size = static_cast<lapack_int>(n);
  const auto band = static_cast<lapack_int>(kd);
  if (LAPACKE_dpbtrf(LAPACK_COL_MAJOR, 'L', size, band, ab, band + 1) != 0)
  {
    return false;
  }
  return LAPACKE_dpbtrs(LAPACK_COL_MAJOR, 'L', size, band, 1, ab, band + 1, b, size) == 0;
}

namespace
{

/// One block row's factors: the diagonal block's own unit-lower L (l10, l20, l21) and D (d0, d1, d2), and
/// the factors of the whole matrix that tie it to the two rows eliminated before it in its chain (row-major
/// 3x3): L(l, l-1) and L(l, l-2) in a chain down the rows, L(p, p+1) and L(p, p+2) in one up them.
struct BlockRow
{
  double l10, l20, l21, d0, d1, d2;
  double inv[3];  ///< 1 / d0, 1 / d1, 1 / d2: each pivot's reciprocal, taken once
  double below1[9];
  double below2[9];
};
static_assert(sizeof(BlockRow) <= 36 * sizeof(double), "solveBlockBanded's work holds 36 doubles a block row");

/// L D L^T of the symmetric 3x3 block s (its lower triangle is read); false unless every pivot is positive.
/// Without branches (a pivot that is not positive leaves the later values meaningless, and the result false),
/// so that two chains' blocks factored one after the other overlap (chainPair).
ROV_TETHER_INLINE bool factorBlock(const double* s, BlockRow& row)
{
  row.d0 = s[0];
  row.l10 = s[3] / row.d0;
  row.l20 = s[6] / row.d0;
  row.d1 = s[4] - row.l10 * s[3];
  row.l21 = (s[7] - row.l20 * s[3]) / row.d1;
  row.d2 = s[8] - row.l20 * s[6] - row.l21 * row.l21 * row.d1;
  row.inv[0] = 1.0 / row.d0, row.inv[1] = 1.0 / row.d1, row.inv[2] = 1.0 / row.d2;
  return row.d0 > 0.0 && row.d1 > 0.0 && row.d2 > 0.0;
}

/// y = a L^-T for the unit-lower L of `row` (each row of a, forward substitution): y L^T = a.
ROV_TETHER_INLINE void solveTransposed(const double* a, const BlockRow& row, double* y)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    y[3 * r] = a[3 * r];
    y[3 * r + 1] = a[3 * r + 1] - row.l10 * y[3 * r];
    y[3 * r + 2] = a[3 * r + 2] - row.l20 * y[3 * r] - row.l21 * y[3 * r + 1];
  }
}

/// s -= y D^-1 y^T (lower triangle) and stores L(l, k) = y D^-1 into `below`.
ROV_TETHER_INLINE void schurUpdate(const double* y, const BlockRow& pivot, double* s, double* below)
{
  const double* inv = pivot.inv;
  for (std::size_t r = 0; r < 3; ++r)
  {
    for (std::size_t c = 0; c < 3; ++c)
    {
      below[3 * r + c] = y[3 * r + c] * inv[c];
    }
  }
  for (std::size_t r = 0; r < 3; ++r)
  {
    for (std::size_t c = 0; c <= r; ++c)
    {
      s[3 * r + c] -= below[3 * r] * y[3 * c] + below[3 * r + 1] * y[3 * c + 1] + below[3 * r + 2] * y[3 * c + 2];
    }
  }
}

/// Y2 = c L^-T for the unit-lower L of `row` (solveTransposed of c I, its zeros left out: the same
/// roundings), upper triangular: y[0], y[1], y[2], y[4], y[5], y[8] are set, the rest is 0.
ROV_TETHER_INLINE void scaledTransposedInverse(double c, const BlockRow& row, double* y)
{
  const double y01 = -(row.l10 * c);
  y[0] = c, y[1] = y01, y[2] = -(row.l20 * c) - row.l21 * y01;
  y[3] = 0.0, y[4] = c, y[5] = -(row.l21 * c);
  y[6] = 0.0, y[7] = 0.0, y[8] = c;
}

/// schurUpdate for the upper-triangular y of scaledTransposedInverse (its zero products left out).
ROV_TETHER_INLINE void schurUpdateUpper(const double* y, const BlockRow& pivot, double* s, double* below)
{
  const double* inv = pivot.inv;
  below[0] = y[0] * inv[0], below[1] = y[1] * inv[1], below[2] = y[2] * inv[2];
  below[3] = 0.0, below[4] = y[4] * inv[1], below[5] = y[5] * inv[2];
  below[6] = 0.0, below[7] = 0.0, below[8] = y[8] * inv[2];
  s[0] -= below[0] * y[0] + below[1] * y[1] + below[2] * y[2];
  s[3] -= below[4] * y[1] + below[5] * y[2];
  s[4] -= below[4] * y[4] + below[5] * y[5];
  s[6] -= below[8] * y[2];
  s[7] -= below[8] * y[5];
  s[8] -= below[8] * y[8];
}

/// out -= y m^T for y upper triangular (scaledTransposedInverse's) and m full: a row's coupling to the row
/// after the one it is eliminated against (and, twisted, what a chain's row leaves between the meeting rows).
ROV_TETHER_INLINE void subtractUpperTimesTransposed(const double* y, const double* m, double* out)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    for (std::size_t col = 0; col < 3; ++col)
    {
      double sum = y[4 * r] * m[3 * col + r];
      for (std::size_t q = r + 1; q < 3; ++q)
      {
        sum += y[3 * r + q] * m[3 * col + q];
      }
      out[3 * r + col] -= sum;
    }
  }
}

/// A block row's elimination against the two rows eliminated before it in its chain (prev1 the last, prev2
/// the one before), in two parts: eliminateSecond against prev2 (A(row, prev2) = c I), then eliminateFirst
/// against prev1 (a1 = A(row, prev1)), which leave s = S_row for factorBlock:
/// s -= Y2 D^-1 Y2^T + Y1 D^-1 Y1^T, with L(row, prev2) into out.below2 and L(row, prev1) into out.below1.
ROV_TETHER_INLINE void eliminateSecond(double* s, double* a1, double c, const BlockRow& prev1, const BlockRow& prev2,
                                       BlockRow& out)
{
  double y2[9];
  scaledTransposedInverse(c, prev2, y2);
  schurUpdateUpper(y2, prev2, s, out.below2);
  subtractUpperTimesTransposed(y2, prev1.below1, a1);  // a1 -= Y2 L(prev1, prev2)^T
}
ROV_TETHER_INLINE void eliminateFirst(double* s, const double* a1, const BlockRow& prev1, BlockRow& out)
{
  double y1[9];
  solveTransposed(a1, prev1, y1);
  schurUpdate(y1, prev1, s, out.below1);
}

/// Block row p's inputs in a chain running down the rows (kReverse false: its last row eliminated is p - 1)
/// or up them (true: p + 1): s = A(p, p), a1 = its coupling to the last row (up the rows, A(p, p + 1), the
/// transpose of the stored A(p + 1, p)) and the c of its coupling c I to the row before (0 without one).
template <bool kSecond, bool kReverse>
ROV_TETHER_INLINE void loadRow(const double* __restrict diag, const double* __restrict first,
                               const double* __restrict second, const BlockLayout& layout, std::size_t p, bool has1,
                               bool has2, double* s, double* a1, double* c)
{
  for (std::size_t i = 0; i < 9; ++i)
  {
    s[i] = diag[p * layout.row + i * layout.entry];
  }
  if (has1)
  {
    const double* stored = first + (kReverse ? p : p - 1) * layout.row;
    for (std::size_t i = 0; i < 9; ++i)
    {
      a1[i] = stored[(kReverse ? 3 * (i % 3) + i / 3 : i) * layout.entry];
    }
  }
  *c = kSecond && has2 ? second[kReverse ? p : p - 2] : 0.0;
}

/// Block row p eliminated against prev1 and prev2 (nullptr where there is none) and factored, in a chain
/// running down the rows or up them (loadRow).
template <bool kSecond, bool kReverse>
ROV_TETHER_INLINE bool chainRow(const double* __restrict diag, const double* __restrict first,
                                const double* __restrict second, const BlockLayout& layout, std::size_t p,
                                const BlockRow* prev1, const BlockRow* prev2, BlockRow& out)
{
  double s[9], a1[9], c = 0.0;
  loadRow<kSecond, kReverse>(diag, first, second, layout, p, prev1 != nullptr, prev2 != nullptr, s, a1, &c);
  if (kSecond && prev2 != nullptr)
  {
    eliminateSecond(s, a1, c, *prev1, *prev2, out);
  }
  if (prev1 != nullptr)
  {
    eliminateFirst(s, a1, *prev1, out);
  }
  return factorBlock(s, out);
}

/// chainRow for row t of the chain down the rows and row p of the chain up them, each step of the one
/// followed by the same step of the other, so that the processor overlaps the two chains' dependent
/// divisions. Both rows have both predecessors (t >= 2, p + 2 < n).
template <bool kSecond>
ROV_TETHER_INLINE bool chainPair(const double* __restrict diag, const double* __restrict first,
                                 const double* __restrict second, const BlockLayout& layout, std::size_t t,
                                 std::size_t p, BlockRow* rows)
{
  double s[2][9], a1[2][9], c[2];
  loadRow<kSecond, false>(diag, first, second, layout, t, true, true, s[0], a1[0], &c[0]);
  loadRow<kSecond, true>(diag, first, second, layout, p, true, true, s[1], a1[1], &c[1]);
  if (kSecond)
  {
    eliminateSecond(s[0], a1[0], c[0], rows[t - 1], rows[t - 2], rows[t]);
    eliminateSecond(s[1], a1[1], c[1], rows[p + 1], rows[p + 2], rows[p]);
  }
  eliminateFirst(s[0], a1[0], rows[t - 1], rows[t]);
  eliminateFirst(s[1], a1[1], rows[p + 1], rows[p]);
  const bool top = factorBlock(s[0], rows[t]);
  const bool bottom = factorBlock(s[1], rows[p]);
  return top && bottom;
}

/// Block L D L^T with block bandwidth 1 or 2 (kSecond): the factors into work; false if not definite.
/// kReverse eliminates the block rows from the last to the first (elimination row l is block row n - 1 - l):
/// the same system, with the first block row's pivot last (solveBlockBandedPulled).
template <bool kSecond, bool kReverse = false>
ROV_TETHER_TARGET_CLONES bool factorBlocks(const double* __restrict diag, const double* __restrict first,
                                           const double* __restrict second, const BlockLayout& layout, std::size_t n,
                                           double* __restrict work)
{
  // A = L D L^T, L unit block-lower with 3x3 unit-lower diagonal blocks L_l and D diagonal; it is the
  // scalar L D L^T of the band in the same order, computed a block row at a time with triangular solves (no
  // explicit inverse, so as stable for a stiff, badly conditioned chain as the scalar one). For row l:
  //   Y2 = A(l, l-2) L_l-2^-T,                       L(l, l-2) = Y2 D_l-2^-1,
  //   Y1 = (A(l, l-1) - Y2 L(l-1, l-2)^T) L_l-1^-T,  L(l, l-1) = Y1 D_l-1^-1,
  //   S_l = A(l, l) - Y1 D_l-1^-1 Y1^T - Y2 D_l-2^-1 Y2^T = L_l D_l L_l^T.
  // A(l, l-2) = c I (second[l - 2] = c), so Y2 is c L_l-2^-T: upper triangular, its zeros skipped.
  // Reversed, A(l, l-1) of the elimination order is the block above the diagonal, the transpose of the one
  // stored below it, and A(l, l-2) the same c I.
  auto* rows = reinterpret_cast<BlockRow*>(work);
  for (std::size_t l = 0; l < n; ++l)
  {
    const std::size_t p = kReverse ? n - 1 - l : l;  // the block row eliminated l-th
    if (!chainRow<kSecond, kReverse>(diag, first, second, layout, p, l >= 1 ? &rows[l - 1] : nullptr,
                                     kSecond && l >= 2 ? &rows[l - 2] : nullptr, rows[l]))
    {
      return false;
    }
  }
  return true;
}

/// The twisted factorisation (factorTwisted) from this many block rows on; below it, factorBlocks.
constexpr std::size_t kTwistedFrom = 8;
// factorTwisted reads rows k-2 and k+3 around its meeting (k = (n - 2) / 2): n >= 6 for bandwidth 2.
static_assert(kTwistedFrom >= 6, "the twisted factorisation needs two rows in each chain");

/// Where factorTwisted's two chains meet: block rows k and k + 1.
inline std::size_t meeting(std::size_t n) { return (n - 2) / 2; }

/// factorTwisted's factors of the meeting rows besides their own BlockRows: L(k, k+2), L(k+1, k-1) (both
/// upper triangular, as every second-band factor) and L(k+1, k). They follow the n BlockRows in work.
struct Meeting
{
  double k_k2[9], k1_km1[9], k1_k[9];
};
// Each further row adds 36 doubles of work and a BlockRow's fewer.
static_assert(kTwistedFrom * sizeof(BlockRow) + sizeof(Meeting) <= kTwistedFrom * 36 * sizeof(double),
              "factorTwisted's factors fit the 36 n doubles of work");
/// The twisted pulled solve keeps the pull's forward pass (3 (k + 2) <= 3 n doubles) in work from kPulledScratch n
/// doubles on, after factorTwisted's factors (n BlockRows and a Meeting).
constexpr std::size_t kPulledScratch = 32;
// From kTwistedFrom rows on (and so on for every larger n, a BlockRow being at most kPulledScratch doubles), the
// factors end before the scratch, and the scratch's 3 n doubles end within the work.
static_assert(sizeof(BlockRow) <= kPulledScratch * sizeof(double) &&
                  kTwistedFrom * sizeof(BlockRow) + sizeof(Meeting) <= kTwistedFrom * kPulledScratch * sizeof(double) &&
                  kPulledScratch + 3 <= 36,
              "the pulled solve's scratch follows the factors within the 36 n doubles of work");

/// factorBlocks in the twisted order: rows 0 .. k-1 eliminated down from the top and rows n-1 .. k+2 up from
/// the bottom, a row of each chain in every pass of one loop (two independent chains of dependent divisions,
/// which the processor overlaps: each alone is latency-bound), then the meeting rows k and k + 1. Neither
/// chain touches the other's rows, only the meeting's: the top's rows k-2 and k-1 reach row k, and row k-1
/// also reaches row k + 1 through the second band; the bottom's rows k+2 and k+3 reach row k + 1, and row
/// k+2 also reaches row k through the second band. The same L D L^T, of the matrix with its rows in that
/// order. n >= kTwistedFrom.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES bool factorTwisted(const double* __restrict diag, const double* __restrict first,
                                            const double* __restrict second, const BlockLayout& layout, std::size_t n,
                                            double* __restrict work)
{
  auto* rows = reinterpret_cast<BlockRow*>(work);
  auto& meet = *reinterpret_cast<Meeting*>(rows + n);
  const std::size_t k = meeting(n);
  const std::size_t bottom = n - 2 - k;  // rows in the bottom chain: k or k + 1
  for (std::size_t i = 0; i < bottom; ++i)
  {
    const std::size_t p = n - 1 - i;
    if (i >= 2 && i < k)
    {
      if (!chainPair<kSecond>(diag, first, second, layout, i, p, rows))
      {
        return false;
      }
      continue;
    }
    const bool top = i >= k || chainRow<kSecond, false>(diag, first, second, layout, i, i >= 1 ? &rows[i - 1] : nullptr,
                                                        kSecond && i >= 2 ? &rows[i - 2] : nullptr, rows[i]);
    if (!top || !chainRow<kSecond, true>(diag, first, second, layout, p, i >= 1 ? &rows[p + 1] : nullptr,
                                         kSecond && i >= 2 ? &rows[p + 2] : nullptr, rows[p]))
    {
      return false;
    }
  }
  // Row k against the top chain, row k + 1 against the bottom chain, as each chain's next row would be.
  double sk[9], sk1[9], a1[9], x[9], c = 0.0;
  loadRow<kSecond, false>(diag, first, second, layout, k, true, true, sk, a1, &c);
  if (kSecond)
  {
    eliminateSecond(sk, a1, c, rows[k - 1], rows[k - 2], rows[k]);
  }
  eliminateFirst(sk, a1, rows[k - 1], rows[k]);
  loadRow<kSecond, true>(diag, first, second, layout, k + 1, true, true, sk1, a1, &c);
  if (kSecond)
  {
    eliminateSecond(sk1, a1, c, rows[k + 2], rows[k + 3], rows[k + 1]);
  }
  eliminateFirst(sk1, a1, rows[k + 2], rows[k + 1]);
  // A(k + 1, k) and what each chain's rows that reach both meeting rows take off it: the bottom's row k + 2
  // reaches row k through the second band, the top's row k - 1 reaches row k + 1 through it.
  for (std::size_t i = 0; i < 9; ++i)
  {
    x[i] = first[k * layout.row + i * layout.entry];
  }
  if (kSecond)
  {
    double y[9];
    scaledTransposedInverse(second[k], rows[k + 2], y);  // A(k, k+2) L_k+2^-T
    schurUpdateUpper(y, rows[k + 2], sk, meet.k_k2);
    // x -= L(k+1, k+2) D (y D^-1)^T = L(k+1, k+2) y^T = (y L(k+1, k+2)^T)^T: subtractUpperTimesTransposed's,
    // transposed.
    double t[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    subtractUpperTimesTransposed(y, rows[k + 1].below1, t);
    for (std::size_t r = 0; r < 3; ++r)
    {
      for (std::size_t col = 0; col < 3; ++col)
      {
        x[3 * r + col] += t[3 * col + r];
      }
    }
    double z[9];
    scaledTransposedInverse(second[k - 1], rows[k - 1], z);  // A(k+1, k-1) L_k-1^-T
    schurUpdateUpper(z, rows[k - 1], sk1, meet.k1_km1);
    subtractUpperTimesTransposed(z, rows[k].below1, x);
  }
  if (!factorBlock(sk, rows[k]))
  {
    return false;
  }
  double y1[9];
  solveTransposed(x, rows[k], y1);
  schurUpdate(y1, rows[k], sk1, meet.k1_k);
  return factorBlock(sk1, rows[k + 1]);
}

/// out -= m v and out -= m^T v for row-major 3x3 m.
ROV_TETHER_INLINE void multiplySubtract(const double* m, const double* v, double* out)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    out[r] -= m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2];
  }
}
ROV_TETHER_INLINE void multiplyTransposedSubtract(const double* m, const double* v, double* out)
{
  for (std::size_t c = 0; c < 3; ++c)
  {
    out[c] -= m[c] * v[0] + m[3 + c] * v[1] + m[6 + c] * v[2];
  }
}

/// u -= m v and x -= m^T v for m upper triangular (a second-band factor: its zeros left out, the same
/// roundings as forwardBlocks' and backwardBlocks').
ROV_TETHER_INLINE void upperSubtract(const double* m, const double* v, double* u)
{
  u[0] -= m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
  u[1] -= m[4] * v[1] + m[5] * v[2];
  u[2] -= m[8] * v[2];
}
ROV_TETHER_INLINE void upperTransposedSubtract(const double* m, const double* v, double* x)
{
  x[0] -= m[0] * v[0];
  x[1] -= m[1] * v[0] + m[4] * v[1];
  x[2] -= m[2] * v[0] + m[5] * v[1] + m[8] * v[2];
}

/// x = D_l^-1 x (the backward pass's first move on a row).
ROV_TETHER_INLINE void divide(const BlockRow& row, double* x) { x[0] /= row.d0, x[1] /= row.d1, x[2] /= row.d2; }

/// x = L_l^-T x for row l's own unit-lower L_l.
ROV_TETHER_INLINE void ownTransposed(const BlockRow& row, double* x)
{
  x[1] -= row.l21 * x[2];
  x[0] -= row.l10 * x[1] + row.l20 * x[2];
}

/// Block row r's values of b in the elimination order (factorBlocks' kReverse).
template <bool kReverse>
ROV_TETHER_INLINE double* at(double* b, std::size_t n, std::size_t r)
{
  return b + 3 * (kReverse ? n - 1 - r : r);
}

/// u_l = L_l^-1 v for the unit-lower L_l of `row`.
ROV_TETHER_INLINE void ownForward(const BlockRow& row, double* u)
{
  u[1] -= row.l10 * u[0];
  u[2] -= row.l20 * u[0] + row.l21 * u[1];
}

/// x = L_l^-T D_l^-1 x for `row`'s own factors.
ROV_TETHER_INLINE void ownBackward(const BlockRow& row, double* x)
{
  divide(row, x);
  ownTransposed(row, x);
}

/// A row's forward step in its chain: u -= L(row, prev1) u1 + L(row, prev2) u2 (u1, u2 nullptr where there is
/// no such row; L(row, prev2) is upper triangular), then u = L_row^-1 u.
template <bool kSecond>
ROV_TETHER_INLINE void forwardRow(const BlockRow& row, const double* u1, const double* u2, double* u)
{
  if (u1 != nullptr)
  {
    multiplySubtract(row.below1, u1, u);
  }
  if (kSecond && u2 != nullptr)
  {
    upperSubtract(row.below2, u2, u);
  }
  ownForward(row, u);
}

/// A row's backward step: x = L_row^-T (D_row^-1 x - m1^T x1 - m2^T x2), m1 and m2 the factors that tie the
/// rows eliminated after it (their unknowns x1 and x2, nullptr where there is none) to it; m2 upper triangular.
template <bool kSecond>
ROV_TETHER_INLINE void backwardRow(const BlockRow& row, const double* m1, const double* x1, const double* m2,
                                   const double* x2, double* x)
{
  divide(row, x);
  if (x1 != nullptr)
  {
    multiplyTransposedSubtract(m1, x1, x);
  }
  if (kSecond && x2 != nullptr)
  {
    upperTransposedSubtract(m2, x2, x);
  }
  ownTransposed(row, x);
}

/// L u = b (block forward), with the factors in work.
template <bool kSecond, bool kReverse>
ROV_TETHER_INLINE void forwardBlocks(double* __restrict b, std::size_t n, const BlockRow* __restrict rows)
{
  for (std::size_t l = 0; l < n; ++l)
  {
    forwardRow<kSecond>(rows[l], l >= 1 ? at<kReverse>(b, n, l - 1) : nullptr,
                        l >= 2 ? at<kReverse>(b, n, l - 2) : nullptr, at<kReverse>(b, n, l));
  }
}

/// D and L^T (block backward), with the factors in work.
template <bool kSecond, bool kReverse>
ROV_TETHER_INLINE void backwardBlocks(double* __restrict b, std::size_t n, const BlockRow* __restrict rows)
{
  for (std::size_t l = n; l-- > 0;)
  {
    const bool one = l + 1 < n, two = l + 2 < n;
    backwardRow<kSecond>(rows[l], one ? rows[l + 1].below1 : nullptr, one ? at<kReverse>(b, n, l + 1) : nullptr,
                         two ? rows[l + 2].below2 : nullptr, two ? at<kReverse>(b, n, l + 2) : nullptr,
                         at<kReverse>(b, n, l));
  }
}

/// L u = b (block forward), then D and L^T (block backward), with the factors in work.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteBlocks(double* __restrict b, std::size_t n, const double* __restrict work)
{
  const auto* rows = reinterpret_cast<const BlockRow*>(work);
  forwardBlocks<kSecond, false>(b, n, rows);
  backwardBlocks<kSecond, false>(b, n, rows);
}

/// The forward pass's meeting rows k and k + 1 (v(p): block row p's values), after both chains. kBottom false:
/// the bottom chain's rows are 0 (the pull's pass of substituteTwistedPulled), and their terms are left out.
template <bool kSecond, bool kBottom, typename Rows>
ROV_TETHER_INLINE void forwardMeeting(std::size_t k, const BlockRow* __restrict rows, const Meeting& meet, Rows v)
{
  multiplySubtract(rows[k].below1, v(k - 1), v(k));
  if (kBottom)
  {
    multiplySubtract(rows[k + 1].below1, v(k + 2), v(k + 1));
  }
  if (kSecond)
  {
    upperSubtract(rows[k].below2, v(k - 2), v(k));
    if (kBottom)
    {
      upperSubtract(meet.k_k2, v(k + 2), v(k));
      upperSubtract(rows[k + 1].below2, v(k + 3), v(k + 1));
    }
    upperSubtract(meet.k1_km1, v(k - 1), v(k + 1));
  }
  ownForward(rows[k], v(k));
  multiplySubtract(meet.k1_k, v(k), v(k + 1));
  ownForward(rows[k + 1], v(k + 1));
}

/// The forward pass after factorTwisted (u = L^-1 b in place): down the top chain and up the bottom chain
/// together, then the meeting rows.
template <bool kSecond>
ROV_TETHER_INLINE void forwardTwisted(double* __restrict b, std::size_t n, const BlockRow* __restrict rows,
                                      const Meeting& meet, double* __restrict q = nullptr)
{
  const std::size_t k = meeting(n);
  const std::size_t bottom = n - 2 - k;
  auto v = [b](std::size_t p) { return b + 3 * p; };
  auto w = [q](std::size_t p) { return q + 3 * p; };
  for (std::size_t i = 0; i < bottom; ++i)
  {
    if (i < k)
    {
      forwardRow<kSecond>(rows[i], i >= 1 ? v(i - 1) : nullptr, i >= 2 ? v(i - 2) : nullptr, v(i));
      if (q != nullptr && i >= 1)
      {
        // The pull's pass (substituteTwistedPulled) beside b's, in the same top chain: its steps overlap.
        forwardRow<kSecond>(rows[i], w(i - 1), i >= 2 ? w(i - 2) : nullptr, w(i));
      }
    }
    const std::size_t p = n - 1 - i;
    forwardRow<kSecond>(rows[p], i >= 1 ? v(p + 1) : nullptr, i >= 2 ? v(p + 2) : nullptr, v(p));
  }
  forwardMeeting<kSecond, true>(k, rows, meet, v);
}

/// The backward pass after forwardTwisted (x = L^-T D^-1 u in place): the meeting rows, then out along both
/// chains together.
template <bool kSecond>
ROV_TETHER_INLINE void backwardTwisted(double* __restrict b, std::size_t n, const BlockRow* __restrict rows,
                                       const Meeting& meet)
{
  const std::size_t k = meeting(n);
  const std::size_t bottom = n - 2 - k;
  auto v = [b](std::size_t p) { return b + 3 * p; };
  divide(rows[k + 1], v(k + 1));
  ownTransposed(rows[k + 1], v(k + 1));
  divide(rows[k], v(k));
  multiplyTransposedSubtract(meet.k1_k, v(k + 1), v(k));
  ownTransposed(rows[k], v(k));
  for (std::size_t i = bottom; i-- > 0;)
  {
    // Top row l = i and bottom row p = n - 1 - i, the meeting's neighbours first.
    if (i < k)
    {
      backwardRow<kSecond>(rows[i], rows[i + 1].below1, v(i + 1), i + 1 == k ? meet.k1_km1 : rows[i + 2].below2,
                           v(i + 2), v(i));
    }
    const std::size_t p = n - 1 - i;
    backwardRow<kSecond>(rows[p], rows[p - 1].below1, v(p - 1), p == k + 2 ? meet.k_k2 : rows[p - 2].below2, v(p - 2),
                         v(p));
  }
}

/// substituteBlocks after factorTwisted: forward down the top chain and up the bottom chain together, the
/// meeting rows, then backward from the meeting rows out along both chains together.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteTwisted(double* __restrict b, std::size_t n, const double* __restrict work)
{
  const auto* rows = reinterpret_cast<const BlockRow*>(work);
  const auto& meet = *reinterpret_cast<const Meeting*>(rows + n);
  forwardTwisted<kSecond>(b, n, rows, meet);
  backwardTwisted<kSecond>(b, n, rows, meet);
}

/// solveBlockBandedPulled's solve after factorTwisted, for a pull f P on block row 1 (in the top chain, as
/// n >= kTwistedFrom makes it): with u = L^-1 b and q = L^-1 P e_1 (forward passes; q is 0 outside block rows
/// 1 .. k + 1, the top chain's and the meeting's), P . x_1 without the pull is q . D^-1 u and P . A^-1_11 P is
/// q . D^-1 q (A^-1 = L^-T D^-1 L^-1); the law sets f from them, and one backward pass of u - f q finishes.
/// `q` holds 3 (k + 2) doubles.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteTwistedPulled(double* __restrict b, std::size_t n,
                                                      const double* __restrict work, double* __restrict q,
                                                      const double* pull, const EndLaw& law, double* force)
{
  const auto* rows = reinterpret_cast<const BlockRow*>(work);
  const auto& meet = *reinterpret_cast<const Meeting*>(rows + n);
  const std::size_t k = meeting(n);
  // q = L^-1 P e_1: down the top chain from row 1 beside b's pass, then the meeting rows (the bottom chain's
  // rows are 0).
  auto v = [q](std::size_t p) { return q + 3 * p; };
  std::fill(q, q + 3 * (k + 2), 0.0);
  q[3] = pull[0], q[4] = pull[1], q[5] = pull[2];
  forwardTwisted<kSecond>(b, n, rows, meet, q);
  forwardMeeting<kSecond, false>(k, rows, meet, v);
  double along = 0.0, compliance = 0.0;
  for (std::size_t p = 1; p <= k + 1; ++p)
  {
    const BlockRow& row = rows[p];
    const double* u = b + 3 * p;
    const double* w = v(p);
    const double scaled[3] = {w[0] / row.d0, w[1] / row.d1, w[2] / row.d2};
    along += scaled[0] * u[0] + scaled[1] * u[1] + scaled[2] * u[2];
    compliance += scaled[0] * w[0] + scaled[1] * w[1] + scaled[2] * w[2];
  }
  const double f = law.force(along, compliance);
  *force = f;
  for (std::size_t i = 3; i < 3 * (k + 2); ++i)
  {
    b[i] -= f * q[i];
  }
  backwardTwisted<kSecond>(b, n, rows, meet);
}

/// solveBlockBandedPulled's solve, after factorBlocks<kSecond, true>.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substitutePulled(double* __restrict b, std::size_t n, const double* __restrict work,
                                               const double* pull, const EndLaw& law, double* force)
{
  // Block row 1 is eliminated last but one, and block row 0 (eliminated last) does not couple to it, so
  // after the forward pass row 1's own factors S_1 = L_1 D_1 L_1^T hold all of A: its unknowns without the
  // pull are x_1 = S_1^-1 ... = L_1^-T D_1^-1 u_1, and A^-1 restricted to it is S_1^-1.
  const auto* rows = reinterpret_cast<const BlockRow*>(work);
  forwardBlocks<kSecond, true>(b, n, rows);
  const BlockRow& row = rows[n - 2];
  const double* u = b + 3;
  double x[3] = {u[0], u[1], u[2]};
  ownBackward(row, x);
  double w[3] = {pull[0], pull[1], pull[2]};
  ownForward(row, w);  // L_1^-1 P
  double z[3] = {w[0], w[1], w[2]};
  ownBackward(row, z);  // S_1^-1 P
  const double along = pull[0] * x[0] + pull[1] * x[1] + pull[2] * x[2];
  const double compliance = pull[0] * z[0] + pull[1] * z[1] + pull[2] * z[2];
  *force = law.force(along, compliance);
  double* v = b + 3;  // b_1 - f P, in the forward pass's terms: u_1 - f L_1^-1 P
  v[0] -= *force * w[0], v[1] -= *force * w[1], v[2] -= *force * w[2];
  backwardBlocks<kSecond, true>(b, n, rows);
}

}  // namespace

bool solveBlockBanded(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                      double* work, const BlockLayout& layout)
{
  const bool twisted = n >= kTwistedFrom;
  if (second != nullptr)
  {
    if (!(twisted ? factorTwisted<true>(diag, first, second, layout, n, work)
                  : factorBlocks<true>(diag, first, second, layout, n, work)))
    {
      return false;
    }
    solveBlockBandedAgain(true, b, n, work);
    return true;
  }
  if (!(twisted ? factorTwisted<false>(diag, first, nullptr, layout, n, work)
                : factorBlocks<false>(diag, first, nullptr, layout, n, work)))
  {
    return false;
  }
  solveBlockBandedAgain(false, b, n, work);
  return true;
}

bool solveBlockBandedPulled(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                            double* work, const double* pull, const EndLaw& law, double* force,
                            const BlockLayout& layout)
{
  // Block row 0 must not couple to the others (A(1, 0) = 0 and A(2, 0) = 0), or block row 1's last pivot would
  // not hold A^-1_11 in the single chain (the twisted solve does not need it; the contract is the same for both).
  bool uncoupled = true;
  for (std::size_t i = 0; i < 9 && n >= 2; ++i)
  {
    uncoupled = uncoupled && first[i * layout.entry] == 0.0;
  }
  if (n < 2 || !uncoupled || (second != nullptr && n > 2 && second[0] != 0.0))
  {
    return false;
  }
  if (n >= kTwistedFrom)
  {
    // Twisted, as solveBlockBanded: block row 1 is in the top chain. The pull's forward pass is kept in the
    // work after the factors.
    double* q = work + kPulledScratch * n;
    if (second != nullptr)
    {
      if (!factorTwisted<true>(diag, first, second, layout, n, work))
      {
        return false;
      }
      substituteTwistedPulled<true>(b, n, work, q, pull, law, force);
      return true;
    }
    if (!factorTwisted<false>(diag, first, nullptr, layout, n, work))
    {
      return false;
    }
    substituteTwistedPulled<false>(b, n, work, q, pull, law, force);
    return true;
  }
  if (second != nullptr)
  {
    if (!factorBlocks<true, true>(diag, first, second, layout, n, work))
    {
      return false;
    }
    substitutePulled<true>(b, n, work, pull, law, force);
    return true;
  }
  if (!factorBlocks<false, true>(diag, first, nullptr, layout, n, work))
  {
    return false;
  }
  substitutePulled<false>(b, n, work, pull, law, force);
  return true;
}

void solveBlockBandedAgain(bool second, double* b, std::size_t n, const double* work)
{
  if (n >= kTwistedFrom)
  {
    second ? substituteTwisted<true>(b, n, work) : substituteTwisted<false>(b, n, work);
  }
  else
  {
    second ? substituteBlocks<true>(b, n, work) : substituteBlocks<false>(b, n, work);
  }
}

bool solveBlockBandedLapack(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                            double* band, const BlockLayout& layout)
{
  const std::size_t kd = second != nullptr ? 8 : 5;
  const std::size_t ld = kd + 1;
  const std::size_t rows = 3 * n;
  std::fill(band, band + ld * rows, 0.0);
  auto put = [band, ld](std::size_t p, std::size_t q, const double* block, std::size_t entry)
  {
    for (std::size_t a = 0; a < 3; ++a)
    {
      for (std::size_t c = 0; c < 3; ++c)
      {
        const std::size_t i = 3 * p + a;
        const std::size_t j = 3 * q + c;
        if (i >= j)
        {
          band[(i - j) + j * ld] = block[(3 * a + c) * entry];
        }
      }
    }
  };
  for (std::size_t l = 0; l < n; ++l)
  {
    put(l, l, diag + l * layout.row, layout.entry);
    if (l + 1 < n)
    {
      put(l + 1, l, first + l * layout.row, layout.entry);
    }
    if (second != nullptr && l + 2 < n)
    {
      const double c = second[l];
      const double block[9] = {c, 0, 0, 0, c, 0, 0, 0, c};
      put(l + 2, l, block, 1);
    }
  }
  return solveBandedLapack(band, kd, b, rows);
}

bool solveBlockBandedLapackAgain(bool second, double* b, std::size_t n, const double* band)
{
  const std::size_t kd = second ? 8 : 5;
  const auto size = static_cast<lapack_int>(3 * n);
  const auto width = static_cast<lapack_int>(kd);
  return LAPACKE_dpbtrs(LAPACK_COL_MAJOR, 'L', size, width, 1, band, width + 1, b, size) == 0;
}

}  // namespace rov_tether::banded
