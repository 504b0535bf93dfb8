#include "rov_tether/banded.hpp"

#include <lapacke.h>

#include <algorithm>
#include <cmath>

namespace rov_tether::banded
{

bool solveTridiagonalSweep(double* d, double* e, double* b, std::size_t n)
{
  // A twisted L D L^T: elimination runs down from the top and up from the bottom at once, meeting at row
  // p, then substitution runs outwards from p. The two halves are independent chains, so their latency
  // (a division each row) overlaps: about twice as fast as one sweep from the top.
  if (n == 0)
  {
    return true;
  }
  const std::size_t p = n / 2;
  const std::size_t down = p;        // top rows 0..p-1 eliminated into the next one
  const std::size_t up = n - 1 - p;  // bottom rows n-1..p+1 eliminated into the one above
  for (std::size_t s = 0; s < down || s < up; ++s)
  {
    if (s < down)
    {
      const std::size_t i = s;
      if (!(d[i] > 0.0))
      {
        return false;
      }
      const double l = e[i] / d[i];
      d[i + 1] -= l * e[i];
      b[i + 1] -= l * b[i];
      e[i] = l;
    }
    if (s < up)
    {
      const std::size_t j = n - 1 - s;
      if (!(d[j] > 0.0))
      {
        return false;
      }
      const double u = e[j - 1] / d[j];
      d[j - 1] -= u * e[j - 1];
      b[j - 1] -= u * b[j];
      e[j - 1] = u;
    }
  }
  if (!(d[p] > 0.0))
  {
    return false;
  }
  b[p] /= d[p];
  for (std::size_t s = 0; s < down || s < up; ++s)
  {
    if (s < down)
    {
      const std::size_t i = p - 1 - s;
      b[i] = b[i] / d[i] - e[i] * b[i + 1];
    }
    if (s < up)
    {
      const std::size_t j = p + 1 + s;
      b[j] = b[j] / d[j] - e[j - 1] * b[j - 1];
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

bool solveBandedSweep(double* ab, std::size_t kd, double* b, std::size_t n)
{
  const std::size_t ld = kd + 1;
  auto at = [ab, ld](std::size_t i, std::size_t j) -> double& { return ab[(i - j) + j * ld]; };
  // Cholesky A = L L^T in the band, column by column (right-looking).
  for (std::size_t j = 0; j < n; ++j)
  {
    if (!(at(j, j) > 0.0))
    {
      return false;
    }
    const double pivot = std::sqrt(at(j, j));
    at(j, j) = pivot;
    const std::size_t last = std::min(n - 1, j + kd);
    for (std::size_t i = j + 1; i <= last; ++i)
    {
      at(i, j) /= pivot;
    }
    for (std::size_t k = j + 1; k <= last; ++k)
    {
      const double ljk = at(k, j);
      for (std::size_t i = k; i <= last; ++i)
      {
        at(i, k) -= at(i, j) * ljk;
      }
    }
  }
  // L y = b, then L^T x = y.
  for (std::size_t j = 0; j < n; ++j)
  {
    b[j] /= at(j, j);
    const std::size_t last = std::min(n - 1, j + kd);
    for (std::size_t i = j + 1; i <= last; ++i)
    {
      b[i] -= at(i, j) * b[j];
    }
  }
  for (std::size_t j = n; j-- > 0;)
  {
    const std::size_t last = std::min(n - 1, j + kd);
    for (std::size_t i = j + 1; i <= last; ++i)
    {
      b[j] -= at(i, j) * b[i];
    }
    b[j] /= at(j, j);
  }
  return true;
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
