#pragma once

#include <cstddef>

namespace rov_tether::banded
{

/**
 * Symmetric positive definite solves of the direct solver, written out (the "sweep") and through LAPACK,
 * so the two can be measured against each other (bench: BM_TridiagonalSolve, BM_BandedSolve). The scalar
 * tridiagonal and band solves are in banded.cpp; the systems of 3x3 blocks in block_banded.cpp (its row
 * steps: block_rows.hpp).
 *
 * Tridiagonal: diagonal d[0..n), off-diagonal e[0..n-1) (e[i] couples i and i+1); b[0..n) is
 * overwritten with the solution; d and e are overwritten with the factors.
 * Banded: the lower band in LAPACK's layout (ldab = kd + 1, column-major: ab[(i - j) + j (kd + 1)] =
 * A(i, j) for j <= i <= j + kd); overwritten with the factors (the sweep: L D L^T, unrolled for the
 * half-bandwidths the direct solver uses, 5 and 8; LAPACK: Cholesky); b overwritten with the solution.
 * Each returns false when the matrix is not positive definite (b is then unusable).
 */
bool solveTridiagonalSweep(double* d, double* e, double* b, std::size_t n);
bool solveTridiagonalLapack(double* d, double* e, double* b, std::size_t n);
bool solveBandedSweep(double* ab, std::size_t kd, double* b, std::size_t n);
bool solveBandedLapack(double* ab, std::size_t kd, double* b, std::size_t n);

/// Where the blocks' entries are: entry i (row-major) of block l at l * row + i * entry. The default is a block
/// after the other (row 9, entry 1); one array an entry is row 1, entry the arrays' length (the direct solver's
/// assembly, which fills them in vectorised loops).
struct BlockLayout
{
  std::size_t row = 9;
  std::size_t entry = 1;
};
/**
 * SPD systems of 3x3 blocks with block bandwidth 1 (block tridiagonal: a cable's positions) or 2 (block
 * pentadiagonal: with bending), by a block L D L^T: one 3x3 inverse a block row instead of three scalar
 * pivots in a chain. From 8 block rows on it is twisted: one chain of block rows eliminated down from the
 * first, one up from the last, a row of each at once (a lane each of two-lane vectors: each chain is a sequence
 * of dependent divisions), meeting in the middle. Blocks are row-major 3x3: diag's block l is A(l, l) for l <
 * n, first's block l is A(l + 1, l) for l < n - 1 (where their entries are: `layout`). The second blocks are multiples
 * of the identity (the direct solver's bending joints, whose curvature is linear in the positions and the same on each
 * axis): second[l] is the one number c of A(l + 2, l) = c I for l < n - 2 (nullptr for bandwidth 1). b holds 3 n values
 * and is overwritten with the solution; `work` needs 36 n doubles, 16-byte aligned (as a std::vector<double>'s data:
 * the twisted factorisation keeps two-lane vectors there). False when not positive definite (b then holds nothing
 * meaningful). Of diag's blocks only the lower triangle (entries 0, 3, 4, 6, 7, 8) is read, here and in the other block
 * solves below: the matrix is symmetric, and the direct solver's assembly writes no other.
 */
bool solveBlockBanded(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                      double* work, const BlockLayout& layout = {});
/// The law that sets a pull's size from the response of the unknowns it acts on (solveBlockBandedPulled).
class EndLaw
{
 public:
  virtual ~EndLaw() = default;
  /// The pull f, given P . x_1 of the solution without it (`along`) and P . A^-1_11 P (`compliance`): with
  /// it, P . x_1 becomes along - f compliance.
  virtual double force(double along, double compliance) const = 0;
};
/// solveBlockBanded of A x = b - f P on block row 1 (P the 3 values of `pull`), with the pull f that `law`
/// sets (into `force`): one factorisation and one substitution. Below 8 block rows it eliminates from the last
/// block row to the first, so that block row 1's last pivot holds A^-1_11; from 8 on it is twisted, as
/// solveBlockBanded, and the pull comes from the forward passes of b and of P on block row 1. False when it is
/// not positive definite (b then holds nothing meaningful), and when n < 2 or block row 0 couples to the others (it
/// must be a pinned particle's: the single chain needs it). The direct solver's spool segment on a drum
/// (PrimalNewton::pulledSolve).
bool solveBlockBandedPulled(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                            double* work, const double* pull, const EndLaw& law, double* force,
                            const BlockLayout& layout = {});
/// Solves the system solveBlockBanded last factored into `work` again, for another right-hand side b.
void solveBlockBandedAgain(bool second, double* b, std::size_t n, const double* work);
/// The same system through LAPACK's band Cholesky (dpbtrf/dpbtrs): the blocks are copied into a band of
/// half-bandwidth 5 (or 8), which `band` must hold ((kd + 1) 3 n doubles).
bool solveBlockBandedLapack(const double* diag, const double* first, const double* second, double* b, std::size_t n,
                            double* band, const BlockLayout& layout = {});
/// Solves with the factor solveBlockBandedLapack left in `band` again, for another right-hand side b.
bool solveBlockBandedLapackAgain(bool second, double* b, std::size_t n, const double* band);

}  // namespace rov_tether::banded
