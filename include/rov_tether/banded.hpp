#pragma once

#include <cstddef>

namespace rov_tether::banded
{

/**
 * Symmetric positive definite solves of the direct solver, written out (the "sweep") and through LAPACK,
 * so the two can be measured against each other (bench: BM_TridiagonalSolve, BM_BandedSolve).
 *
 * Tridiagonal: diagonal d[0..n), off-diagonal e[0..n-1) (e[i] couples i and i+1); b[0..n) is
 * overwritten with the solution; d and e are overwritten with the factors.
 * Banded: the lower band in LAPACK's layout (ldab = kd + 1, column-major: ab[(i - j) + j (kd + 1)] =
 * A(i, j) for j <= i <= j + kd); overwritten with the Cholesky factor; b overwritten with the solution.
 * Each returns false when the matrix is not positive definite (b is then unusable).
 */
bool solveTridiagonalSweep(double* d, double* e, double* b, std::size_t n);
bool solveTridiagonalLapack(double* d, double* e, double* b, std::size_t n);
bool solveBandedSweep(double* ab, std::size_t kd, double* b, std::size_t n);
bool solveBandedLapack(double* ab, std::size_t kd, double* b, std::size_t n);

}  // namespace rov_tether::banded
