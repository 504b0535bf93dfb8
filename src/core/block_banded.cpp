#include <lapacke.h>

#include <algorithm>

#include "banded.hpp"
#include "block_rows.hpp"
#include "simd.hpp"
#include "twisted_rows.hpp"

namespace rov_tether::banded
{

namespace
{

using namespace block;  // the loops over block_rows.hpp's row steps

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

/// factorBlocks in the twisted order: rows 0 .. k-1 eliminated down from the top and rows n-1 .. k+2 up from
/// the bottom, a row of each chain in every pass of one loop (two independent chains of dependent divisions,
/// taken a lane each of one stream of vector instructions from row 2 on), then the meeting rows k and k + 1. Neither
/// chain touches the other's rows, only the meeting's: the top's rows k-2 and k-1 reach row k, and row k-1
/// also reaches row k + 1 through the second band; the bottom's rows k+2 and k+3 reach row k + 1, and row
/// k+2 also reaches row k through the second band. The same L D L^T, of the matrix with its rows in that
/// order; the factors where TwistedRows says. n >= kTwistedFrom. With b, the forward pass of b (and of q, with
/// it) goes along with it (TwistedForward): b (and q) then hold L^-1 b (and L^-1 q) when it returns true.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES bool factorTwisted(const double* __restrict diag, const double* __restrict first,
                                            const double* __restrict second, const BlockLayout& layout, std::size_t n,
                                            double* __restrict work, double* b = nullptr, double* q = nullptr)
{
  const TwistedRows rows(work, n);
  const std::size_t k = rows.k();
  TwistedForward<kSecond> forward(b, rows, q);
  // Rows 0 and 1 of each chain, one at a time.
  for (std::size_t i = 0; i < 2; ++i)
  {
    const std::size_t p = n - 1 - i;
    if (!chainRow<kSecond, false>(diag, first, second, layout, i, i >= 1 ? &rows.single(0) : nullptr, nullptr,
                                  rows.single(i)) ||
        !chainRow<kSecond, true>(diag, first, second, layout, p, i >= 1 ? &rows.single(n - 1) : nullptr, nullptr,
                                 rows.single(p)))
    {
      return false;
    }
  }
  if (b != nullptr)
  {
    forward.start();
  }
  // Rows 2 .. k-1 of the top chain and n-3 .. n-k of the bottom one, a row of each at once (chainPair, a lane
  // each), into pair i, against the two pairs before it (rows 0 and 1 of each chain side by side for the first two).
  // A pair's factors chainPair does not set (below2 without a second band) are never read, here or in the
  // substitutions: what the work held there is carried along.
  PairRow start[2];
  gather(values(rows.single(0)), values(rows.single(n - 1)), 27, values(start[0]));
  gather(values(rows.single(1)), values(rows.single(n - 2)), 27, values(start[1]));
  for (std::size_t i = 2; i < k; ++i)
  {
    const PairRow& prev1 = i >= 3 ? rows.pair(i - 1) : start[1];
    const PairRow& prev2 = i >= 4 ? rows.pair(i - 2) : start[i - 2];
    if (!chainPair<kSecond>(diag, first, second, layout, i, n - 1 - i, prev1, prev2, rows.pair(i)))
    {
      return false;
    }
    if (b != nullptr)
    {
      forward.pair(i);
    }
  }
  // The rows next to the meeting, as BlockRows (from their pairs' lanes, or rows in no pair): k - 1 and k - 2, and
  // k + 2 and k + 3. With n odd, row k + 2 is the bottom chain's last, in no pair.
  const BlockRow top1 = rows.row(k - 1), top2 = rows.row(k - 2), bottom2 = rows.row(k + 3);
  if (n % 2 == 1)
  {
    const BlockRow low2 = rows.row(k + 4);
    if (!chainRow<kSecond, true>(diag, first, second, layout, k + 2, &bottom2, &low2, rows.single(k + 2)))
    {
      return false;
    }
  }
  const BlockRow bottom1 = rows.row(k + 2);
  BlockRow& rk = rows.single(k);
  BlockRow& rk1 = rows.single(k + 1);
  Meeting& meet = rows.meet();
  // Row k against the top chain, row k + 1 against the bottom chain, as each chain's next row would be.
  double sk[9], sk1[9], a1[9], x[9], c = 0.0;
  loadRow<kSecond, false>(diag, first, second, layout, k, true, true, sk, a1, &c);
  if (kSecond)
  {
    eliminateSecond(sk, a1, c, top1, top2, rk);
  }
  eliminateFirst(sk, a1, top1, rk);
  loadRow<kSecond, true>(diag, first, second, layout, k + 1, true, true, sk1, a1, &c);
  if (kSecond)
  {
    eliminateSecond(sk1, a1, c, bottom1, bottom2, rk1);
  }
  eliminateFirst(sk1, a1, bottom1, rk1);
  // A(k + 1, k) and what each chain's rows that reach both meeting rows take off it: the bottom's row k + 2
  // reaches row k through the second band, the top's row k - 1 reaches row k + 1 through it.
  for (std::size_t i = 0; i < 9; ++i)
  {
    x[i] = first[k * layout.row + i * layout.entry];
  }
  if (kSecond)
  {
    double y[9];
    scaledTransposedInverse(second[k], bottom1, y);  // A(k, k+2) L_k+2^-T
    schurUpdateUpper(y, bottom1, sk, meet.k_k2);
    // x -= L(k+1, k+2) D (y D^-1)^T = L(k+1, k+2) y^T = (y L(k+1, k+2)^T)^T: subtractUpperTimesTransposed's,
    // transposed.
    double t[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    subtractUpperTimesTransposed(y, rk1.below1, t);
    for (std::size_t r = 0; r < 3; ++r)
    {
      for (std::size_t col = 0; col < 3; ++col)
      {
        x[3 * r + col] += t[3 * col + r];
      }
    }
    double z[9];
    scaledTransposedInverse(second[k - 1], top1, z);  // A(k+1, k-1) L_k-1^-T
    schurUpdateUpper(z, top1, sk1, meet.k1_km1);
    subtractUpperTimesTransposed(z, rk.below1, x);
  }
  if (!factorBlock(sk, rk))
  {
    return false;
  }
  double y1[9];
  solveTransposed(x, rk, y1);
  schurUpdate(y1, rk, sk1, meet.k1_k);
  if (!factorBlock(sk1, rk1))
  {
    return false;
  }
  if (b != nullptr)
  {
    forward.finish();
  }
  return true;
}

/// L u = b (block forward), then D and L^T (block backward), with the factors in work.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteBlocks(double* __restrict b, std::size_t n, const double* __restrict work)
{
  const auto* rows = reinterpret_cast<const BlockRow*>(work);
  forwardBlocks<kSecond, false>(b, n, rows);
  backwardBlocks<kSecond, false>(b, n, rows);
}

/// substituteBlocks after factorTwisted: forward down the top chain and up the bottom chain together, the
/// meeting rows, then backward from the meeting rows out along both chains together.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteTwisted(double* __restrict b, std::size_t n, const double* __restrict work)
{
  const TwistedRows rows(work, n);
  forwardTwisted<kSecond>(b, rows);
  backwardTwisted<kSecond>(b, rows);
}

/// The backward pass alone, after factorTwisted with b (its forward pass along with it).
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteTwistedBackward(double* __restrict b, std::size_t n,
                                                        const double* __restrict work)
{
  backwardTwisted<kSecond>(b, TwistedRows(work, n));
}

/// solveBlockBandedPulled's solve after factorTwisted, for a pull f P on block row 1 (in the top chain, as
/// n >= kTwistedFrom makes it): with u = L^-1 b and q = L^-1 P e_1 (forward passes; q is 0 outside block rows
/// 1 .. k + 1, the top chain's and the meeting's), P . x_1 without the pull is q . D^-1 u and P . A^-1_11 P is
/// q . D^-1 q (A^-1 = L^-T D^-1 L^-1); the law sets f from them, and one backward pass of u - f q finishes.
/// `q` holds 3 (k + 2) doubles: P e_1, 0 elsewhere (pulledStart), which factorTwisted's forward pass, along with
/// b's, has made L^-1 P e_1.
template <bool kSecond>
ROV_TETHER_TARGET_CLONES void substituteTwistedPulled(double* __restrict b, std::size_t n,
                                                      const double* __restrict work, double* __restrict q,
                                                      const EndLaw& law, double* force)
{
  const TwistedRows rows(work, n);
  const std::size_t k = rows.k();
  auto v = [q](std::size_t p) { return q + 3 * p; };
  double along = 0.0, compliance = 0.0;
  for (std::size_t p = 1; p <= k + 1; ++p)
  {
    // Row p's pivots: lane 0 of its pair (2 <= p < k), or its own BlockRow.
    const bool paired = p >= 2 && p < k;
    const double d0 = paired ? rows.pair(p).d0[0] : rows.single(p).d0;
    const double d1 = paired ? rows.pair(p).d1[0] : rows.single(p).d1;
    const double d2 = paired ? rows.pair(p).d2[0] : rows.single(p).d2;
    const double* u = b + 3 * p;
    const double* w = v(p);
    const double scaled[3] = {w[0] / d0, w[1] / d1, w[2] / d2};
    along += scaled[0] * u[0] + scaled[1] * u[1] + scaled[2] * u[2];
    compliance += scaled[0] * w[0] + scaled[1] * w[1] + scaled[2] * w[2];
  }
  const double f = law.force(along, compliance);
  *force = f;
  for (std::size_t i = 3; i < 3 * (k + 2); ++i)
  {
    b[i] -= f * q[i];
  }
  backwardTwisted<kSecond>(b, rows);
}

/// The pull's right-hand side for the twisted pulled solve: P on block row 1 (the top chain's), 0 on the rest of
/// the top chain and the meeting rows (3 (k + 2) values of q).
void pulledStart(double* q, std::size_t n, const double* pull)
{
  std::fill(q, q + 3 * (meeting(n) + 2), 0.0);
  q[3] = pull[0], q[4] = pull[1], q[5] = pull[2];
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
  if (n >= kTwistedFrom)
  {
    // The forward pass along with the factorisation, then the backward pass.
    if (!(second != nullptr ? factorTwisted<true>(diag, first, second, layout, n, work, b)
                            : factorTwisted<false>(diag, first, nullptr, layout, n, work, b)))
    {
      return false;
    }
    second != nullptr ? substituteTwistedBackward<true>(b, n, work) : substituteTwistedBackward<false>(b, n, work);
    return true;
  }
  if (!(second != nullptr ? factorBlocks<true>(diag, first, second, layout, n, work)
                          : factorBlocks<false>(diag, first, nullptr, layout, n, work)))
  {
    return false;
  }
  solveBlockBandedAgain(second != nullptr, b, n, work);
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
    pulledStart(q, n, pull);
    if (second != nullptr)
    {
      if (!factorTwisted<true>(diag, first, second, layout, n, work, b, q))
      {
        return false;
      }
      substituteTwistedPulled<true>(b, n, work, q, law, force);
      return true;
    }
    if (!factorTwisted<false>(diag, first, nullptr, layout, n, work, b, q))
    {
      return false;
    }
    substituteTwistedPulled<false>(b, n, work, q, law, force);
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
