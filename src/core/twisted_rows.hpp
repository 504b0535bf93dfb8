#pragma once
// The twisted block L D L^T's factors in the work (TwistedRows: where each block row's factors are kept) and its
// substitutions (forwardTwisted, forwardMeeting, backwardTwisted), for block_banded.cpp's factorTwisted and
// solves. Inline, for block_banded.cpp's loops (each compiled there for every instruction set); private to the
// core.
#include <cassert>
#include <cstddef>
#include <cstdint>

#include "block_rows.hpp"

namespace rov_tether::banded::block
{

/// The twisted factorisation (factorTwisted) from this many block rows on; below it, factorBlocks.
constexpr std::size_t kTwistedFrom = 8;
// factorTwisted reads rows k-2 and k+3 around its meeting (k = (n - 2) / 2): n >= 6 for bandwidth 2.
static_assert(kTwistedFrom >= 6, "the twisted factorisation needs two rows in each chain");

/// Where factorTwisted's two chains meet: block rows k and k + 1.
inline std::size_t meeting(std::size_t n) { return (n - 2) / 2; }

/// factorTwisted's factors of the meeting rows besides their own BlockRows: L(k, k+2), L(k+1, k-1) (both
/// upper triangular, as every second-band factor) and L(k+1, k).
struct Meeting
{
  double k_k2[9], k1_km1[9], k1_k[9];
};

/// Where factorTwisted keeps a block row's factors in the work (36 n doubles, aligned as a std::vector's). The
/// rows eliminated in pairs come first, a PairRow a pair as the elimination made them (pair i, 2 <= i < k: the top
/// chain's row i in lane 0 and the bottom chain's row n - 1 - i in lane 1), so that the substitutions load both
/// rows' factors at once; then the rows in no pair, a BlockRow each (0, 1, n - 1, n - 2, k, k + 1, and k + 2 when
/// n is odd); then the Meeting. n BlockRows and a Meeting in all, as 2 BlockRows are a PairRow.
class TwistedRows
{
 public:
  TwistedRows(double* work, std::size_t n)
      : n_(n),
        k_(meeting(n)),
        pairs_(reinterpret_cast<PairRow*>(work)),
        single_(reinterpret_cast<BlockRow*>(pairs_ + (k_ - 2))),
        meet_(reinterpret_cast<Meeting*>(single_ + 6 + n % 2))
  {
    assert(n >= kTwistedFrom && reinterpret_cast<std::uintptr_t>(work) % alignof(PairRow) == 0);
  }
  TwistedRows(const double* work, std::size_t n) : TwistedRows(const_cast<double*>(work), n) {}

  std::size_t k() const { return k_; }
  /// Rows in the bottom chain: k or k + 1 (n odd: the last, row k + 2, is in no pair).
  std::size_t bottom() const { return n_ - 2 - k_; }
  /// Pair i's two rows (2 <= i < k).
  PairRow& pair(std::size_t i) const { return pairs_[i - 2]; }
  /// Row p's BlockRow, for a row in no pair.
  BlockRow& single(std::size_t p) const
  {
    const std::size_t n = n_, k = k_;
    return single_[p == 0 ? 0 : p == 1 ? 1 : p == n - 1 ? 2 : p == n - 2 ? 3 : p == k ? 4 : p == k + 1 ? 5 : 6];
  }
  /// Row p's factors, whether it is in a pair (its lane of it) or not.
  BlockRow row(std::size_t p) const
  {
    const bool top = p >= 2 && p < k_, bottom = p + 3 <= n_ && p >= n_ - k_;
    if (!top && !bottom)
    {
      return single(p);
    }
    const Lanes* from = values(pair(top ? p : n_ - 1 - p));
    BlockRow out;
    double* to = values(out);
    for (std::size_t j = 0; j < 27; ++j)
    {
      to[j] = from[j][top ? 0 : 1];
    }
    return out;
  }
  Meeting& meet() const { return *meet_; }

 private:
  std::size_t n_, k_;
  PairRow* pairs_;
  BlockRow* single_;
  Meeting* meet_;
};
// The pairs and the single rows take n BlockRows (2 a pair), and each further row adds 36 doubles of work.
static_assert(sizeof(PairRow) == 2 * sizeof(BlockRow) && alignof(PairRow) <= 16 &&
                  kTwistedFrom * sizeof(BlockRow) + sizeof(Meeting) <= kTwistedFrom * 36 * sizeof(double),
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

/// The forward pass's meeting rows k and k + 1 (rk and rk1 their factors; v(p): block row p's values), after both
/// chains. kBottom false: the bottom chain's rows are 0 (the pull's pass of substituteTwistedPulled), and their
/// terms are left out.
template <bool kSecond, bool kBottom, typename Rows>
ROV_TETHER_INLINE void forwardMeeting(std::size_t k, const BlockRow& rk, const BlockRow& rk1, const Meeting& meet,
                                      Rows v)
{
  multiplySubtract(rk.below1, v(k - 1), v(k));
  if (kBottom)
  {
    multiplySubtract(rk1.below1, v(k + 2), v(k + 1));
  }
  if (kSecond)
  {
    upperSubtract(rk.below2, v(k - 2), v(k));
    if (kBottom)
    {
      upperSubtract(meet.k_k2, v(k + 2), v(k));
      upperSubtract(rk1.below2, v(k + 3), v(k + 1));
    }
    upperSubtract(meet.k1_km1, v(k - 1), v(k + 1));
  }
  ownForward(rk, v(k));
  multiplySubtract(meet.k1_k, v(k), v(k + 1));
  ownForward(rk1, v(k + 1));
}

/// The forward pass after factorTwisted (u = L^-1 b in place), in the order factorTwisted makes the rows, so that
/// it can also go along with the factorisation (each step as soon as its rows are factored; the divisions of the
/// factorisation's chains leave the processor the time): start() rows 0 and 1 of both chains, pair(i) pair i's two
/// rows a lane each (their values gathered from b and scattered back, the last two pairs' kept for the next),
/// finish() the bottom chain's last row when n is odd, then the meeting rows. With q, the pull's pass
/// (substituteTwistedPulled: q = L^-1 P e_1, 0 but in the top chain and the meeting) beside b's, its rows in the
/// pairs' lane 0 (lane 1 kept 0).
template <bool kSecond>
class TwistedForward
{
 public:
  TwistedForward(double* b, const TwistedRows& rows, double* q)
      : b_(b), q_(q), rows_(rows), k_(rows.k()), n_(rows.k() + 2 + rows.bottom())
  {
  }
  void start()
  {
    const std::size_t n = n_;
    for (std::size_t i = 0; i < 2; ++i)
    {
      const double* none = nullptr;
      forwardRow<kSecond>(rows_.single(i), i >= 1 ? v(i - 1) : none, none, v(i));
      forwardRow<kSecond>(rows_.single(n - 1 - i), i >= 1 ? v(n - i) : none, none, v(n - 1 - i));
    }
    // u1 and u2 hold the last two pairs' values (rows i - 1, n - i and i - 2, n + 1 - i), as q1 and q2 the pull's.
    gather(v(1), v(n - 2), 3, u1_);
    gather(v(0), v(n - 1), 3, u2_);
    if (q_ != nullptr)
    {
      forwardRow<kSecond>(rows_.single(1), w(0), static_cast<const double*>(nullptr), w(1));
      for (std::size_t j = 0; j < 3; ++j)
      {
        q1_[j] = Lanes{w(1)[j], 0.0}, q2_[j] = Lanes{w(0)[j], 0.0};
      }
    }
  }
  void pair(std::size_t i)
  {
    const std::size_t p = n_ - 1 - i;
    const PairRow& pair = rows_.pair(i);
    Lanes u[3];
    gather(v(i), v(p), 3, u);
    forwardRow<kSecond>(pair, u1_, u2_, u);
    scatter(u, 3, v(i), v(p));
    for (std::size_t j = 0; j < 3; ++j)
    {
      u2_[j] = u1_[j], u1_[j] = u[j];
    }
    if (q_ != nullptr)
    {
      // The pull's row i beside b's: the same factors, lane 1 a row of zeros.
      Lanes r[3] = {Lanes{w(i)[0], 0.0}, Lanes{w(i)[1], 0.0}, Lanes{w(i)[2], 0.0}};
      forwardRow<kSecond>(pair, q1_, q2_, r);
      for (std::size_t j = 0; j < 3; ++j)
      {
        w(i)[j] = r[j][0];
        q2_[j] = q1_[j], q1_[j] = r[j];
      }
    }
  }
  void finish()
  {
    const std::size_t k = k_;
    if (n_ % 2 == 1)
    {
      forwardRow<kSecond>(rows_.single(k + 2), v(k + 3), v(k + 4), v(k + 2));  // the bottom chain's last row
    }
    forwardMeeting<kSecond, true>(k, rows_.single(k), rows_.single(k + 1), rows_.meet(),
                                  [this](std::size_t p) { return v(p); });
    if (q_ != nullptr)
    {
      forwardMeeting<kSecond, false>(k, rows_.single(k), rows_.single(k + 1), rows_.meet(),
                                     [this](std::size_t p) { return w(p); });
    }
  }

 private:
  double* v(std::size_t p) const { return b_ + 3 * p; }
  double* w(std::size_t p) const { return q_ + 3 * p; }

  double* b_;
  double* q_;
  const TwistedRows& rows_;
  std::size_t k_, n_;
  Lanes u1_[3], u2_[3], q1_[3] = {}, q2_[3] = {};
};

/// The whole forward pass after factorTwisted (TwistedForward's steps one after the other).
template <bool kSecond>
ROV_TETHER_INLINE void forwardTwisted(double* __restrict b, const TwistedRows& rows)
{
  TwistedForward<kSecond> forward(b, rows, nullptr);
  forward.start();
  for (std::size_t i = 2; i < rows.k(); ++i)
  {
    forward.pair(i);
  }
  forward.finish();
}

/// The backward pass after forwardTwisted (x = L^-T D^-1 u in place): the meeting rows, then out along both
/// chains together, a pair's rows a lane each (the last two pairs' values kept for the next).
template <bool kSecond>
ROV_TETHER_INLINE void backwardTwisted(double* __restrict b, const TwistedRows& rows)
{
  const std::size_t k = rows.k(), bottom = rows.bottom(), n = k + 2 + bottom;
  const Meeting& meet = rows.meet();
  auto v = [b](std::size_t p) { return b + 3 * p; };
  const BlockRow &rk = rows.single(k), &rk1 = rows.single(k + 1);
  divide(rk1, v(k + 1));
  ownTransposed(rk1, v(k + 1));
  divide(rk, v(k));
  multiplyTransposedSubtract(meet.k1_k, v(k + 1), v(k));
  ownTransposed(rk, v(k));
  if (bottom > k)
  {
    // n odd: the bottom chain's last row, k + 2, against row k + 1 and (its second band) row k.
    backwardRow<kSecond>(rows.single(k + 2), rk1.below1, v(k + 1), meet.k_k2, v(k), v(k + 2));
  }
  // Pair i's factors that tie the rows eliminated after it to its rows, and those rows' values: pair i + 1's and
  // i + 2's, as the pairs hold them, but next to the meeting and at the chains' first rows, gathered from there.
  // Top row i + 1 is row k (i + 1 == k) or in no pair (i == 0); top row i + 2 is row k + 1 and the meeting's
  // L(k+1, k-1) (i + 1 == k) or row k (i + 2 == k). The bottom rows n - 2 - i and n - 3 - i likewise (p - 1 and
  // p - 2; row k + 2 is tied to row k by the meeting's L(k, k+2)).
  // The first pair out from the meeting, k - 1 (rows k - 1 and n - k), is tied to rows k, k + 1 and n - k - 1,
  // n - k - 2.
  Lanes x1[3], x2[3], m1[9], m2[9];
  gather(v(k), v(n - k - 1), 3, x1);
  gather(v(k + 1), v(n - k - 2), 3, x2);
  for (std::size_t i = k; i-- > 0;)
  {
    const std::size_t p = n - 1 - i;
    const Lanes *tie1 = m1, *tie2 = m2;
    if (i + 1 < k && i + 1 >= 2)
    {
      tie1 = rows.pair(i + 1).below1;
    }
    else
    {
      gather(rows.single(i + 1).below1, rows.single(p - 1).below1, 9, m1);
    }
    if (kSecond && i + 2 < k)
    {
      tie2 = rows.pair(i + 2).below2;
    }
    else if (kSecond)
    {
      gather(i + 1 == k ? meet.k1_km1 : rows.single(i + 2).below2, p == k + 2 ? meet.k_k2 : rows.single(p - 2).below2,
             9, m2);
    }
    Lanes x[3];
    gather(v(i), v(p), 3, x);
    if (i >= 2)
    {
      backwardRow<kSecond>(rows.pair(i), tie1, x1, tie2, x2, x);
    }
    else
    {
      PairRow own;
      gather(values(rows.single(i)), values(rows.single(p)), 6, values(own));  // the own factors alone
      backwardRow<kSecond>(own, tie1, x1, tie2, x2, x);
    }
    scatter(x, 3, v(i), v(p));
    for (std::size_t j = 0; j < 3; ++j)
    {
      x2[j] = x1[j], x1[j] = x[j];
    }
  }
}

}  // namespace rov_tether::banded::block
