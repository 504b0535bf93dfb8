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

}  // namespace rov_tether::banded
