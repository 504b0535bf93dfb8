#pragma once
// LU without pivoting of a small matrix whose symmetric part is positive definite (a vehicle body's step).

#include <Eigen/Core>

namespace rov_tether
{

/**
 * A = L U by Gaussian elimination without row exchanges, for an N x N matrix A (fixed N) whose symmetric part
 * (A + A^T) / 2 is positive definite: a symmetric positive definite matrix (a vehicle's M + h D) or one plus a
 * skew-symmetric part (the Cayley transform's M + h/2 C). Such a matrix needs no pivoting: x^T A x > 0 for
 * every x != 0, so every leading block is nonsingular and every Schur complement keeps a positive definite
 * symmetric part (Golub and Van Loan, Matrix Computations, 4th ed. 2013, sec. 4.4.4); the pivots are at least
 * the smallest eigenvalue of the symmetric part. The loops have fixed bounds, so the compiler unrolls them: far
 * cheaper at 6 x 6 than Eigen's LDLT or partialPivLu, whose row exchanges and blocked loops dominate there; the
 * unroll pragmas (GCC) take a 6 x 6 factorisation and solve from 829 to 367 instructions. No allocation.
 */
template <int N>
class PositiveRealLu
{
 public:
  using Matrix = Eigen::Matrix<double, N, N>;

  /// Factors `a` (its symmetric part positive definite; not checked).
  void compute(const Matrix& a)
  {
    lu_ = a;
#pragma GCC unroll 8
    for (int k = 0; k < N; ++k)
    {
      inverse_pivot_[k] = 1.0 / lu_(k, k);
#pragma GCC unroll 8
      for (int i = k + 1; i < N; ++i)
      {
        const double factor = lu_(i, k) * inverse_pivot_[k];
        lu_(i, k) = factor;  // L below the diagonal (unit diagonal), U on and above it
#pragma GCC unroll 8
        for (int j = k + 1; j < N; ++j)
        {
          lu_(i, j) -= factor * lu_(k, j);
        }
      }
    }
  }

  /// x with A x = b, for each column of b.
  template <int Cols>
  Eigen::Matrix<double, N, Cols> solve(Eigen::Matrix<double, N, Cols> b) const
  {
#pragma GCC unroll 8
    for (int k = 0; k < N; ++k)
    {
#pragma GCC unroll 8
      for (int i = k + 1; i < N; ++i)
      {
        b.row(i) -= lu_(i, k) * b.row(k);
      }
    }
#pragma GCC unroll 8
    for (int i = N - 1; i >= 0; --i)
    {
#pragma GCC unroll 8
      for (int j = i + 1; j < N; ++j)
      {
        b.row(i) -= lu_(i, j) * b.row(j);
      }
      b.row(i) *= inverse_pivot_[i];
    }
    return b;
  }

 private:
  Matrix lu_ = Matrix::Identity();
  // 1 / U's diagonal: N divisions a factorisation, none in a solve (a division's latency is several
  // multiplications', and the back substitution's are in series).
  Eigen::Matrix<double, N, 1> inverse_pivot_ = Eigen::Matrix<double, N, 1>::Ones();
};

}  // namespace rov_tether
