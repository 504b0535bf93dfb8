#pragma once
// A block row of the direct solver's block L D L^T (banded::solveBlockBanded, block_banded.cpp): its factors,
// the steps that eliminate and factor one block row (or a pair of them, a lane each), and the steps of the forward
// and backward substitutions on one row; the twisted factorisation's layout and passes are in twisted_rows.hpp. Inline,
// for block_banded.cpp's loops (each compiled there for every instruction set); private to the core.
#include <cstddef>

#include "banded.hpp"
#include "simd.hpp"

namespace rov_tether::banded::block
{

/// One block row's factors: the diagonal block's own unit-lower L (l10, l20, l21) and D (d0, d1, d2), and
/// the factors of the whole matrix that tie it to the two rows eliminated before it in its chain (row-major
/// 3x3): L(l, l-1) and L(l, l-2) in a chain down the rows, L(p, p+1) and L(p, p+2) in one up them.
template <typename T>
struct RowFactors
{
  T l10, l20, l21, d0, d1, d2;
  T inv[3];  ///< 1 / d0, 1 / d1, 1 / d2: each pivot's reciprocal, taken once
  T below1[9];
  T below2[9];
};
using BlockRow = RowFactors<double>;
/// Two block rows' values side by side, one a lane (GCC's vector extension: SSE2 in the baseline clone): the
/// twisted factorisation's two chains, a row of each, eliminated by one stream of instructions (chainPair). Each
/// lane is the same operations in the same order as a row's own (no FMA contraction: simd.hpp), so the same
/// roundings.
using Lanes = double __attribute__((vector_size(16)));
using PairRow = RowFactors<Lanes>;
static_assert(sizeof(BlockRow) <= 36 * sizeof(double), "solveBlockBanded's work holds 36 doubles a block row");

/// L D L^T of the symmetric 3x3 block s (its lower triangle is read), of one row or of two a lane each; factorBlock
/// then says whether every pivot is positive. Without branches (a pivot that is not positive leaves the later values
/// meaningless, and the result false).
template <typename T>
ROV_TETHER_INLINE void factorValues(const T* s, RowFactors<T>& row)
{
  row.d0 = s[0];
  row.l10 = s[3] / row.d0;
  row.l20 = s[6] / row.d0;
  row.d1 = s[4] - row.l10 * s[3];
  row.l21 = (s[7] - row.l20 * s[3]) / row.d1;
  row.d2 = s[8] - row.l20 * s[6] - row.l21 * row.l21 * row.d1;
  row.inv[0] = 1.0 / row.d0, row.inv[1] = 1.0 / row.d1, row.inv[2] = 1.0 / row.d2;
}
ROV_TETHER_INLINE bool factorBlock(const double* s, BlockRow& row)
{
  factorValues(s, row);
  return row.d0 > 0.0 && row.d1 > 0.0 && row.d2 > 0.0;
}
/// factorBlock of two rows, one a lane: false unless every pivot of both is positive.
ROV_TETHER_INLINE bool factorBlock(const Lanes* s, PairRow& row)
{
  factorValues(s, row);
  const auto positive = (row.d0 > 0.0) & (row.d1 > 0.0) & (row.d2 > 0.0);
  return (positive[0] & positive[1]) != 0;
}

/// y = a L^-T for the unit-lower L of `row` (each row of a, forward substitution): y L^T = a.
template <typename T>
ROV_TETHER_INLINE void solveTransposed(const T* a, const RowFactors<T>& row, T* y)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    y[3 * r] = a[3 * r];
    y[3 * r + 1] = a[3 * r + 1] - row.l10 * y[3 * r];
    y[3 * r + 2] = a[3 * r + 2] - row.l20 * y[3 * r] - row.l21 * y[3 * r + 1];
  }
}

/// s -= y D^-1 y^T (lower triangle) and stores L(l, k) = y D^-1 into `below`.
template <typename T>
ROV_TETHER_INLINE void schurUpdate(const T* y, const RowFactors<T>& pivot, T* s, T* below)
{
  const T* inv = pivot.inv;
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
template <typename T>
ROV_TETHER_INLINE void scaledTransposedInverse(T c, const RowFactors<T>& row, T* y)
{
  const T y01 = -(row.l10 * c);
  y[0] = c, y[1] = y01, y[2] = -(row.l20 * c) - row.l21 * y01;
  y[3] = T{}, y[4] = c, y[5] = -(row.l21 * c);
  y[6] = T{}, y[7] = T{}, y[8] = c;
}

/// schurUpdate for the upper-triangular y of scaledTransposedInverse (its zero products left out).
template <typename T>
ROV_TETHER_INLINE void schurUpdateUpper(const T* y, const RowFactors<T>& pivot, T* s, T* below)
{
  const T* inv = pivot.inv;
  below[0] = y[0] * inv[0], below[1] = y[1] * inv[1], below[2] = y[2] * inv[2];
  below[3] = T{}, below[4] = y[4] * inv[1], below[5] = y[5] * inv[2];
  below[6] = T{}, below[7] = T{}, below[8] = y[8] * inv[2];
  s[0] -= below[0] * y[0] + below[1] * y[1] + below[2] * y[2];
  s[3] -= below[4] * y[1] + below[5] * y[2];
  s[4] -= below[4] * y[4] + below[5] * y[5];
  s[6] -= below[8] * y[2];
  s[7] -= below[8] * y[5];
  s[8] -= below[8] * y[8];
}

/// out -= y m^T for y upper triangular (scaledTransposedInverse's) and m full: a row's coupling to the row
/// after the one it is eliminated against (and, twisted, what a chain's row leaves between the meeting rows).
template <typename T>
ROV_TETHER_INLINE void subtractUpperTimesTransposed(const T* y, const T* m, T* out)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    for (std::size_t col = 0; col < 3; ++col)
    {
      T sum = y[4 * r] * m[3 * col + r];
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
template <typename T>
ROV_TETHER_INLINE void eliminateSecond(T* s, T* a1, T c, const RowFactors<T>& prev1, const RowFactors<T>& prev2,
                                       RowFactors<T>& out)
{
  T y2[9];
  scaledTransposedInverse(c, prev2, y2);
  schurUpdateUpper(y2, prev2, s, out.below2);
  subtractUpperTimesTransposed(y2, prev1.below1, a1);  // a1 -= Y2 L(prev1, prev2)^T
}
template <typename T>
ROV_TETHER_INLINE void eliminateFirst(T* s, const T* a1, const RowFactors<T>& prev1, RowFactors<T>& out)
{
  T y1[9];
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

/// A row's factors as an array (RowFactors holds nothing but its 27 values; the first 6 are its own, l10 .. d2).
template <typename T>
ROV_TETHER_INLINE T* values(RowFactors<T>& row)
{
  static_assert(sizeof(RowFactors<T>) == 27 * sizeof(T), "RowFactors is its 27 values");
  return reinterpret_cast<T*>(&row);
}
template <typename T>
ROV_TETHER_INLINE const T* values(const RowFactors<T>& row)
{
  return values(const_cast<RowFactors<T>&>(row));
}

/// `count` values of two rows side by side (top in lane 0, bottom in lane 1), and back.
ROV_TETHER_INLINE void gather(const double* top, const double* bottom, std::size_t count, Lanes* out)
{
  for (std::size_t j = 0; j < count; ++j)
  {
    out[j] = Lanes{top[j], bottom[j]};
  }
}
ROV_TETHER_INLINE void scatter(const Lanes* in, std::size_t count, double* top, double* bottom)
{
  for (std::size_t j = 0; j < count; ++j)
  {
    top[j] = in[j][0];
    bottom[j] = in[j][1];
  }
}

/// chainRow for row t of the chain down the rows (lane 0) and row p of the chain up them (lane 1) at once,
/// against their chains' last two rows (prev1, prev2), each lane's operations those of chainRow on its row.
/// Both rows have both predecessors (t >= 2, p + 2 < n).
template <bool kSecond>
ROV_TETHER_INLINE bool chainPair(const double* __restrict diag, const double* __restrict first,
                                 const double* __restrict second, const BlockLayout& layout, std::size_t t,
                                 std::size_t p, const PairRow& prev1, const PairRow& prev2, PairRow& out)
{
  // loadRow's inputs, down the rows for t and up them for p (A(p, p + 1): the stored A(p + 1, p) transposed).
  Lanes s[9], a1[9];
  for (std::size_t i = 0; i < 9; ++i)
  {
    s[i] = Lanes{diag[t * layout.row + i * layout.entry], diag[p * layout.row + i * layout.entry]};
    a1[i] = Lanes{first[(t - 1) * layout.row + i * layout.entry],
                  first[p * layout.row + (3 * (i % 3) + i / 3) * layout.entry]};
  }
  if (kSecond)
  {
    eliminateSecond(s, a1, Lanes{second[t - 2], second[p]}, prev1, prev2, out);
  }
  eliminateFirst(s, a1, prev1, out);
  return factorBlock(s, out);
}

/// out -= m v and out -= m^T v for row-major 3x3 m.
template <typename T>
ROV_TETHER_INLINE void multiplySubtract(const T* m, const T* v, T* out)
{
  for (std::size_t r = 0; r < 3; ++r)
  {
    out[r] -= m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2];
  }
}
template <typename T>
ROV_TETHER_INLINE void multiplyTransposedSubtract(const T* m, const T* v, T* out)
{
  for (std::size_t c = 0; c < 3; ++c)
  {
    out[c] -= m[c] * v[0] + m[3 + c] * v[1] + m[6 + c] * v[2];
  }
}

/// u -= m v and x -= m^T v for m upper triangular (a second-band factor: its zeros left out, the same
/// roundings as forwardBlocks' and backwardBlocks').
template <typename T>
ROV_TETHER_INLINE void upperSubtract(const T* m, const T* v, T* u)
{
  u[0] -= m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
  u[1] -= m[4] * v[1] + m[5] * v[2];
  u[2] -= m[8] * v[2];
}
template <typename T>
ROV_TETHER_INLINE void upperTransposedSubtract(const T* m, const T* v, T* x)
{
  x[0] -= m[0] * v[0];
  x[1] -= m[1] * v[0] + m[4] * v[1];
  x[2] -= m[2] * v[0] + m[5] * v[1] + m[8] * v[2];
}

/// x = D_l^-1 x (the backward pass's first move on a row).
template <typename T>
ROV_TETHER_INLINE void divide(const RowFactors<T>& row, T* x)
{
  x[0] /= row.d0, x[1] /= row.d1, x[2] /= row.d2;
}

/// x = L_l^-T x for row l's own unit-lower L_l.
template <typename T>
ROV_TETHER_INLINE void ownTransposed(const RowFactors<T>& row, T* x)
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
template <typename T>
ROV_TETHER_INLINE void ownForward(const RowFactors<T>& row, T* u)
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
template <bool kSecond, typename T>
ROV_TETHER_INLINE void forwardRow(const RowFactors<T>& row, const T* u1, const T* u2, T* u)
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
template <bool kSecond, typename T>
ROV_TETHER_INLINE void backwardRow(const RowFactors<T>& row, const T* m1, const T* x1, const T* m2, const T* x2, T* x)
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

}  // namespace rov_tether::banded::block
