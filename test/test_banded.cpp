// The direct solver's linear solves: the sweeps written in banded.cpp against LAPACK and against the
// residual of the system they solve; and the vehicle body's 6x6 solves (PositiveRealLu, BodyLu).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "banded.hpp"
#include "rov_tether/core/body_lu.hpp"
#include "rov_tether/core/positive_real_lu.hpp"

namespace rov_tether::test
{
namespace
{

/// A random symmetric tridiagonal matrix made positive definite by a diagonal margin over the off-diagonals
/// (each row's diagonal exceeds the sum of |off| by `margin` x that sum: margin 0 is a singular limit).
struct Tridiagonal
{
  std::vector<double> d, e, b;
  Tridiagonal(std::size_t n, double margin, unsigned seed)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    d.assign(n, 0.0), e.assign(n > 0 ? n - 1 : 0, 0.0), b.assign(n, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i)
    {
      e[i] = u(rng) * std::pow(10.0, 2.0 * u(rng));  // four decades of coupling
    }
    for (std::size_t i = 0; i < n; ++i)
    {
      const double sum = (i > 0 ? std::abs(e[i - 1]) : 0.0) + (i + 1 < n ? std::abs(e[i]) : 0.0);
      d[i] = (1.0 + margin) * sum + 1e-3;
      b[i] = u(rng);
    }
  }
  /// Largest |A x - b| / (|A| |x|) row by row.
  double residual(const std::vector<double>& x) const
  {
    double worst = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i)
    {
      double ax = d[i] * x[i];
      double scale = std::abs(d[i] * x[i]);
      if (i > 0)
      {
        ax += e[i - 1] * x[i - 1], scale += std::abs(e[i - 1] * x[i - 1]);
      }
      if (i + 1 < d.size())
      {
        ax += e[i] * x[i + 1], scale += std::abs(e[i] * x[i + 1]);
      }
      worst = std::max(worst, std::abs(ax - b[i]) / (scale + std::abs(b[i])));
    }
    return worst;
  }
};

// The division-free twisted L D L^T solves what LAPACK's dpttrf/dpttrs solves, to rounding: the backward
// error (relative residual) is a small multiple of the machine epsilon, 2.2e-16, here bounded by 1e-13,
// at every size around the twist point and its rescaling period, and for matrices close to singular (the
// chain of a nearly straight cable is a Laplacian) where the pivots get small.
TEST(Banded, TridiagonalSweepSolvesTheSystem)
{
  for (std::size_t n : {1u, 2u, 3u, 7u, 8u, 9u, 16u, 17u, 100u, 1001u})
  {
    for (double margin : {1.0, 1e-2, 1e-6})
    {
      const Tridiagonal system(n, margin, static_cast<unsigned>(n * 7 + 1));
      std::vector<double> d = system.d, e = system.e, x = system.b;
      std::vector<double> dl = system.d, el = system.e, xl = system.b;
      ASSERT_TRUE(banded::solveTridiagonalSweep(d.data(), e.data(), x.data(), n)) << n;
      ASSERT_TRUE(banded::solveTridiagonalLapack(dl.data(), el.data(), xl.data(), n)) << n;
      EXPECT_LT(system.residual(x), 1e-13) << "n " << n << " margin " << margin;
      for (std::size_t i = 0; i < n; ++i)
      {
        EXPECT_NEAR(x[i], xl[i], 1e-9 * (std::abs(xl[i]) + 1.0)) << "n " << n << " row " << i;
      }
    }
  }
}

// Minors of ten thousand rows of 1e6 (or 1e-6) times each other overflow (underflow) a double unless they are
// rescaled: the sweep rescales them exactly by powers of two.
TEST(Banded, TridiagonalSweepSurvivesHugeAndTinyPivots)
{
  for (double scale : {1e6, 1e-6})
  {
    const std::size_t n = 10000;
    std::vector<double> d(n, 2.5 * scale), e(n - 1, -scale), b(n, 1.0);
    std::vector<double> x = b;
    std::vector<double> dc = d, ec = e;
    ASSERT_TRUE(banded::solveTridiagonalSweep(dc.data(), ec.data(), x.data(), n));
    for (std::size_t i = 0; i < n; ++i)
    {
      const double ax = d[i] * x[i] + (i > 0 ? e[i - 1] * x[i - 1] : 0.0) + (i + 1 < n ? e[i] * x[i + 1] : 0.0);
      ASSERT_NEAR(ax, 1.0, 1e-12) << "scale " << scale << " row " << i;
    }
  }
}

// Not positive definite (a negative pivot on either side of the twist, or at it): refused.
TEST(Banded, TridiagonalSweepRefusesIndefiniteMatrices)
{
  for (std::size_t bad : {0u, 3u, 5u, 9u})
  {
    std::vector<double> d(10, 2.0), e(9, -1.0), b(10, 1.0);
    d[bad] = -1.0;
    EXPECT_FALSE(banded::solveTridiagonalSweep(d.data(), e.data(), b.data(), 10)) << bad;
  }
}

/// A random SPD matrix of 3x3 blocks with block bandwidth 1 or 2, built directly: symmetric random blocks,
/// second blocks random multiples of the identity (as the bending joints make them), then a diagonal that
/// dominates the row sums.
struct BlockSystem
{
  std::vector<double> diag, first, second, b;
  std::size_t n;
  bool two;
  BlockSystem(std::size_t blocks, bool bandwidth_two, unsigned seed) : n(blocks), two(bandwidth_two)
  {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    diag.assign(9 * n, 0.0), first.assign(9 * n, 0.0), second.assign(n, 0.0), b.assign(3 * n, 0.0);
    for (std::size_t i = 0; i < 9 * n; ++i)
    {
      first[i] = u(rng);
    }
    for (std::size_t l = 0; l < n; ++l)
    {
      second[l] = two ? 0.5 * u(rng) : 0.0;
    }
    for (std::size_t l = 0; l < n; ++l)
    {
      for (std::size_t a = 0; a < 3; ++a)
      {
        for (std::size_t c = 0; c <= a; ++c)
        {
          const double v = a == c ? 0.0 : u(rng);
          diag[9 * l + 3 * a + c] = diag[9 * l + 3 * c + a] = v;
        }
        b[3 * l + a] = u(rng);
      }
    }
    for (std::size_t r = 0; r < 3 * n; ++r)
    {
      double sum = 0.0;
      for (std::size_t c = 0; c < 3 * n; ++c)
      {
        sum += c == r ? 0.0 : std::abs(at(r, c));
      }
      diag[9 * (r / 3) + 4 * (r % 3)] = sum + 0.1;
    }
  }
  double at(std::size_t r, std::size_t c) const
  {
    const std::size_t p = r / 3, q = c / 3;
    const std::size_t lo = std::min(p, q), hi = std::max(p, q);
    const std::size_t a = (p >= q ? r : c) % 3, k = (p >= q ? c : r) % 3;  // row of the lower block, column
    if (hi == lo)
    {
      return diag[9 * lo + 3 * (r % 3) + c % 3];
    }
    if (hi == lo + 1 && hi < n)
    {
      return first[9 * lo + 3 * a + k];
    }
    if (two && hi == lo + 2 && hi < n)
    {
      return a == k ? second[lo] : 0.0;
    }
    return 0.0;
  }
};

// The block L D L^T (one 3x3 inverse a block row) solves the block tridiagonal and pentadiagonal systems of
// the direct solver's primal path as LAPACK's band Cholesky does, and with a residual at rounding level. From
// 8 block rows on it is twisted (two chains meeting at rows (n - 2) / 2 and the one after): 8 and 10 give the
// chains as many rows each, 9 and 11 the bottom one more.
TEST(Banded, BlockSolveSolvesTheSystem)
{
  for (bool two : {false, true})
  {
    for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 101u})
    {
      const BlockSystem system(n, two, static_cast<unsigned>(n + (two ? 100 : 0)));
      std::vector<double> x = system.b, xl = system.b, work(36 * n), band(9 * 3 * n);
      const double* second = two ? system.second.data() : nullptr;
      ASSERT_TRUE(banded::solveBlockBanded(system.diag.data(), system.first.data(), second, x.data(), n, work.data()));
      ASSERT_TRUE(
          banded::solveBlockBandedLapack(system.diag.data(), system.first.data(), second, xl.data(), n, band.data()));
      for (std::size_t r = 0; r < 3 * n; ++r)
      {
        double ax = 0.0;
        for (std::size_t c = 0; c < 3 * n; ++c)
        {
          ax += system.at(r, c) * x[c];
        }
        EXPECT_NEAR(ax, system.b[r], 1e-12) << "bandwidth " << (two ? 2 : 1) << " n " << n << " row " << r;
        EXPECT_NEAR(x[r], xl[r], 1e-10) << "bandwidth " << (two ? 2 : 1) << " n " << n << " row " << r;
      }
      // A second right-hand side through the factors each left (the drum's second solve, the end's columns).
      std::vector<double> b2(3 * n);
      for (std::size_t r = 0; r < 3 * n; ++r)
      {
        b2[r] = std::cos(static_cast<double>(r));
      }
      std::vector<double> y = b2, yl = b2;
      banded::solveBlockBandedAgain(two, y.data(), n, work.data());
      ASSERT_TRUE(banded::solveBlockBandedLapackAgain(two, yl.data(), n, band.data()));
      for (std::size_t r = 0; r < 3 * n; ++r)
      {
        double ay = 0.0, ayl = 0.0;
        for (std::size_t c = 0; c < 3 * n; ++c)
        {
          ay += system.at(r, c) * y[c];
          ayl += system.at(r, c) * yl[c];
        }
        EXPECT_NEAR(ay, b2[r], 1e-12) << "again, bandwidth " << (two ? 2 : 1) << " n " << n << " row " << r;
        EXPECT_NEAR(ayl, b2[r], 1e-12) << "LAPACK again, bandwidth " << (two ? 2 : 1) << " n " << n << " row " << r;
      }
    }
  }
}

/// A spring on block row 1's unknowns along P: stretch s0 + P . x_1, force k times it. Given the response
/// without the pull (`along`) and P . A^-1_11 P (`compliance`), the force that meets the law at the solution is
/// k (s0 + along) / (1 + k compliance). It records what it was given.
class SpringLaw : public banded::EndLaw
{
 public:
  SpringLaw(double k, double s0) : k_(k), s0_(s0) {}
  double force(double along, double compliance) const override
  {
    along_ = along, compliance_ = compliance;
    return k_ * (s0_ + along) / (1.0 + k_ * compliance);
  }
  double k_, s0_;
  mutable double along_ = 0.0, compliance_ = 0.0;
};

// The drum's solve in one pass (one factorisation, one substitution; eliminating from the last block row below 8
// rows, twisted from 8 on)
// against its definition: x = A^-1 (b - f P e_1) with the law met at x (a spring: f = k (s0 + P . x_1)), and
// the law handed P . x_1 without the pull and P . A^-1_11 P, each checked against two plain solves. Block row
// 0 is uncoupled (the pinned spool particle); the systems' first blocks are not symmetric, so A(l, l+1) must
// be read as the transpose of the stored A(l+1, l). Rounding-level bounds, as BlockSolveSolvesTheSystem's.
TEST(Banded, PulledSolveMeetsItsLawInOneFactorisation)
{
  for (bool two : {false, true})
  {
    for (std::size_t n : {2u, 3u, 4u, 8u, 9u, 10u, 101u})
    {
      BlockSystem system(n, two, static_cast<unsigned>(7 * n + (two ? 1 : 0)));
      std::fill(system.first.begin(), system.first.begin() + 9, 0.0);  // block row 0 uncoupled
      system.second[0] = 0.0;
      const double* second = two ? system.second.data() : nullptr;
      const double pull[3] = {0.6, -0.48, 0.64};  // unit
      SpringLaw law(3.0, 0.2);
      std::vector<double> x = system.b, work(36 * n);
      double force = 0.0;
      ASSERT_TRUE(banded::solveBlockBandedPulled(system.diag.data(), system.first.data(), second, x.data(), n,
                                                 work.data(), pull, law, &force));
      const std::string where = std::string("bandwidth ") + (two ? "2" : "1") + " n " + std::to_string(n);
      for (std::size_t r = 0; r < 3 * n; ++r)
      {
        double ax = 0.0;
        for (std::size_t c = 0; c < 3 * n; ++c)
        {
          ax += system.at(r, c) * x[c];
        }
        const double rhs = system.b[r] - (r / 3 == 1 ? force * pull[r % 3] : 0.0);
        EXPECT_NEAR(ax, rhs, 1e-12) << where << " row " << r;
      }
      const double stretch = law.s0_ + pull[0] * x[3] + pull[1] * x[4] + pull[2] * x[5];
      EXPECT_NEAR(force, law.k_ * stretch, 1e-12 * std::max(1.0, std::abs(force))) << where;
      // What the law was given, from two plain solves: b, and a unit pull P on block row 1.
      std::vector<double> p = system.b, q(3 * n, 0.0), work2(36 * n);
      q[3] = pull[0], q[4] = pull[1], q[5] = pull[2];
      ASSERT_TRUE(banded::solveBlockBanded(system.diag.data(), system.first.data(), second, p.data(), n, work2.data()));
      banded::solveBlockBandedAgain(two, q.data(), n, work2.data());
      EXPECT_NEAR(law.along_, pull[0] * p[3] + pull[1] * p[4] + pull[2] * p[5], 1e-12) << where;
      EXPECT_NEAR(law.compliance_, pull[0] * q[3] + pull[1] * q[4] + pull[2] * q[5], 1e-12) << where;
    }
  }
  // Refused where block row 1's pivot would not hold A^-1_11: block row 0 coupled to row 1 or row 2; one block.
  for (int coupled : {1, 2})
  {
    BlockSystem system(6, true, 99);
    std::fill(system.first.begin(), system.first.begin() + 9, 0.0);
    system.second[0] = coupled == 2 ? 0.3 : 0.0;
    system.first[4] = coupled == 1 ? 0.3 : 0.0;
    std::vector<double> x = system.b, work(36 * 6);
    double force = 0.0;
    SpringLaw law(3.0, 0.2);
    const double pull[3] = {1.0, 0.0, 0.0};
    EXPECT_FALSE(banded::solveBlockBandedPulled(system.diag.data(), system.first.data(), system.second.data(), x.data(),
                                                6, work.data(), pull, law, &force))
        << "block row 0 coupled to row " << coupled;
  }
  BlockSystem one(1, false, 5);
  std::vector<double> x = one.b, work(36);
  double force = 0.0;
  const double pull[3] = {1.0, 0.0, 0.0};
  EXPECT_FALSE(banded::solveBlockBandedPulled(one.diag.data(), one.first.data(), nullptr, x.data(), 1, work.data(),
                                              pull, SpringLaw(3.0, 0.2), &force));
}

/// `blocks` (9 doubles a block, one after the other) as one array an entry, each `stride` long.
std::vector<double> entryArrays(const std::vector<double>& blocks, std::size_t stride)
{
  std::vector<double> arrays(9 * stride, std::nan(""));  // what no block fills is never read
  for (std::size_t l = 0; 9 * l < blocks.size() && l < stride; ++l)
  {
    for (std::size_t i = 0; i < 9; ++i)
    {
      arrays[i * stride + l] = blocks[9 * l + i];
    }
  }
  return arrays;
}

/// The pull expectTheSameSolutions' pulled solves take (a unit vector), and the coupled checks after it.
constexpr double kPull[3] = {0.6, -0.48, 0.64};

/// The block solves (plain or twisted, LAPACK's and the pulled one, with SpringLaw(3, 0.2)) of `system` as it is
/// and of the same system given as `diag` and `first` in `layout` (system's b and second band): the same numbers,
/// bit for bit. Block row 0 must be uncoupled, for the pull.
void expectTheSameSolutions(const BlockSystem& system, const std::vector<double>& diag,
                            const std::vector<double>& first, const banded::BlockLayout& layout,
                            const std::string& where)
{
  const std::size_t n = system.n;
  const double* second = system.two ? system.second.data() : nullptr;
  std::vector<double> work(36 * n), band(9 * 3 * n);
  std::vector<double> x = system.b, y = system.b;
  ASSERT_TRUE(banded::solveBlockBanded(system.diag.data(), system.first.data(), second, x.data(), n, work.data()));
  ASSERT_TRUE(banded::solveBlockBanded(diag.data(), first.data(), second, y.data(), n, work.data(), layout));
  EXPECT_EQ(x, y) << where;
  x = system.b, y = system.b;
  ASSERT_TRUE(
      banded::solveBlockBandedLapack(system.diag.data(), system.first.data(), second, x.data(), n, band.data()));
  ASSERT_TRUE(banded::solveBlockBandedLapack(diag.data(), first.data(), second, y.data(), n, band.data(), layout));
  EXPECT_EQ(x, y) << "LAPACK, " << where;
  x = system.b, y = system.b;
  double fx = 0.0, fy = 0.0;
  ASSERT_TRUE(banded::solveBlockBandedPulled(system.diag.data(), system.first.data(), second, x.data(), n, work.data(),
                                             kPull, SpringLaw(3.0, 0.2), &fx));
  ASSERT_TRUE(banded::solveBlockBandedPulled(diag.data(), first.data(), second, y.data(), n, work.data(), kPull,
                                             SpringLaw(3.0, 0.2), &fy, layout));
  EXPECT_EQ(x, y) << "pulled, " << where;
  EXPECT_EQ(fx, fy) << "pulled, " << where;
}

// The direct solver's assembly stores the blocks one array an entry (BlockLayout{1, stride}): every solve reads
// the same matrix there as from blocks one after the other, so it gives the same answer to the bit (the same
// operations on the same numbers); the pulled solve's check that block row 0 is uncoupled reads it there too.
// A stride longer than the rows, as the solver's (its particles reserved), and sizes on both sides of the twist.
TEST(Banded, OneArrayAnEntryIsTheSameSystem)
{
  for (bool two : {false, true})
  {
    for (std::size_t n : {3u, 9u, 101u})
    {
      BlockSystem system(n, two, static_cast<unsigned>(3 * n + (two ? 1 : 0)));
      std::fill(system.first.begin(), system.first.begin() + 9, 0.0);  // block row 0 uncoupled, for the pull
      system.second[0] = 0.0;
      const std::size_t stride = n + 3;
      const banded::BlockLayout layout{1, stride};
      const std::vector<double> diag = entryArrays(system.diag, stride), first = entryArrays(system.first, stride);
      const double* second = two ? system.second.data() : nullptr;
      const std::string where = std::string("bandwidth ") + (two ? "2" : "1") + " n " + std::to_string(n);
      expectTheSameSolutions(system, diag, first, layout, where);
      std::vector<double> work(36 * n), y = system.b;
      double fy = 0.0;
      for (std::size_t entry : {1u, 5u})
      {
        std::vector<double> coupled = first;
        coupled[entry * stride] = 0.3;  // entry `entry` of A(1, 0)
        EXPECT_FALSE(banded::solveBlockBandedPulled(diag.data(), coupled.data(), second, y.data(), n, work.data(),
                                                    kPull, SpringLaw(3.0, 0.2), &fy, layout))
            << "block row 0 coupled through entry " << entry << ", " << where;
      }
    }
  }
}

// Only the lower triangle of the diagonal blocks is read (banded.hpp; the direct solver's assembly writes no
// other): with entries 1, 2 and 5 of every diagonal block NaN, every block solve (plain, twisted, pulled and
// LAPACK's) gives the same numbers as with them, bit for bit (a NaN read would reach the solution). Sizes below
// and from kTwistedFrom (8), bandwidth 1 and 2. Fails if a solve reads the upper triangle.
TEST(Banded, TheDiagonalBlocksUpperTriangleIsNotRead)
{
  for (bool two : {false, true})
  {
    for (std::size_t n : {3u, 9u, 101u})
    {
      BlockSystem system(n, two, static_cast<unsigned>(5 * n + (two ? 1 : 0)));
      std::fill(system.first.begin(), system.first.begin() + 9, 0.0);  // block row 0 uncoupled, for the pull
      if (two)
      {
        system.second[0] = 0.0;
      }
      std::vector<double> upper = system.diag;
      for (std::size_t l = 0; l < n; ++l)
      {
        for (std::size_t entry : {1u, 2u, 5u})
        {
          upper[9 * l + entry] = std::numeric_limits<double>::quiet_NaN();
        }
      }
      expectTheSameSolutions(system, upper, system.first, banded::BlockLayout{},
                             std::string("bandwidth ") + (two ? "2" : "1") + " n " + std::to_string(n));
    }
  }
}

// A block that is not positive definite is refused.
TEST(Banded, BlockSolveRefusesIndefiniteMatrices)
{
  // A negative diagonal entry in any block row of a twisted solve, in the top chain, the bottom chain or a
  // meeting row (rows 3 and 4 of 9, 4 and 5 of 10): the matrix is indefinite (one negative eigenvalue: a
  // rank-one change of an SPD matrix), so that row's pivots must refuse it. On each of the three axes, so that
  // each of the block's three pivots is the one that goes negative.
  for (bool two : {false, true})
  {
    for (std::size_t n : {9u, 10u})
    {
      for (std::size_t p = 0; p < 3 * n; ++p)
      {
        BlockSystem system(n, two, static_cast<unsigned>(11 * n + p));
        system.diag[9 * (p / 3) + 4 * (p % 3)] = -10.0;
        std::vector<double> x = system.b, work(36 * n);
        EXPECT_FALSE(banded::solveBlockBanded(system.diag.data(), system.first.data(),
                                              two ? system.second.data() : nullptr, x.data(), n, work.data()))
            << "bandwidth " << (two ? 2 : 1) << " n " << n << " block row " << p / 3 << " axis " << p % 3;
      }
    }
  }

  BlockSystem system(5, false, 3);
  system.diag[9 * 2 + 4] = -10.0;  // the middle diagonal entry of block 2
  std::vector<double> x = system.b, work(36 * 5);
  EXPECT_FALSE(banded::solveBlockBanded(system.diag.data(), system.first.data(), nullptr, x.data(), 5, work.data()));
  std::vector<double> band(9 * 3 * 5);
  x = system.b;
  EXPECT_FALSE(
      banded::solveBlockBandedLapack(system.diag.data(), system.first.data(), nullptr, x.data(), 5, band.data()));
  // Every diagonal block positive definite (the identity), the whole not: blocks 0 and 2 coupled by 2 I make
  // [I 2I; 2I I], whose eigenvalues are 3 and -1; the second block row's pivots find it, through both solves.
  const std::vector<double> identity = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::vector<double> diag, first(9 * 3, 0.0), second = {2.0, 0.0, 0.0};
  for (int l = 0; l < 3; ++l)
  {
    diag.insert(diag.end(), identity.begin(), identity.end());
  }
  std::vector<double> y(9, 1.0);
  EXPECT_FALSE(banded::solveBlockBanded(diag.data(), first.data(), second.data(), y.data(), 3, work.data()));
  y.assign(9, 1.0);
  EXPECT_FALSE(banded::solveBlockBandedLapack(diag.data(), first.data(), second.data(), y.data(), 3, band.data()));
}

/// A rows x cols matrix of entries uniform in [-1, 1].
Eigen::MatrixXd randomMatrix(std::mt19937& rng, int rows, int cols)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i)
  {
    for (int j = 0; j < cols; ++j)
    {
      m(i, j) = u(rng);
    }
  }
  return m;
}

/// PositiveRealLu (a vehicle body's 6x6 solves, no pivoting) on the matrices it is for: A = M + S, M symmetric
/// positive definite (random, eigenvalues over three decades, like a mass matrix with added inertia) and S
/// skew-symmetric up to 10x M's norm (the Cayley transform's h/2 C at a fast turn), or S = 0 (M + h D).
/// Elimination on a matrix with a positive definite symmetric part is backward stable without pivoting
/// (Golub and Van Loan 2013, sec. 4.4.4), so the residual |A x - b| stays within a few eps |A| |x|: bound
/// 100 eps, with one, and three right-hand sides; and x within kappa(A) 100 eps of Eigen's pivoted LU.
TEST(PositiveRealLu, SolvesMatricesWithAPositiveDefiniteSymmetricPart)
{
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  std::mt19937 rng(25);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random = [&](int rows, int cols) { return randomMatrix(rng, rows, cols); };
  constexpr double kEps = 2.220446049250313e-16;
  for (int trial = 0; trial < 200; ++trial)
  {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(random(6, 6));
    const Matrix6 q = qr.householderQ();
    Eigen::Matrix<double, 6, 1> eigenvalues;
    for (int i = 0; i < 6; ++i)
    {
      eigenvalues[i] = std::pow(10.0, 1.5 * (u(rng) + 1.0));  // 1 to 1000
    }
    const Matrix6 m = q * eigenvalues.asDiagonal() * q.transpose();
    const Matrix6 half = random(6, 6);
    const Matrix6 skew = trial % 4 == 0 ? Matrix6::Zero() : Matrix6(half - half.transpose());
    const Matrix6 a = m + (10.0 * u(rng) * m.norm() / std::max(skew.norm(), 1e-300)) * skew;
    PositiveRealLu<6> lu;
    lu.compute(a);
    const Eigen::Matrix<double, 6, 1> b = random(6, 1);
    const Eigen::Matrix<double, 6, 1> x = lu.solve(b);
    EXPECT_LT((a * x - b).norm(), 100.0 * kEps * a.norm() * x.norm()) << "trial " << trial;
    const Eigen::Matrix<double, 6, 1> pivoted = a.partialPivLu().solve(b);
    const double kappa = a.norm() * a.inverse().norm();
    EXPECT_LT((x - pivoted).norm(), 100.0 * kEps * kappa * pivoted.norm()) << "trial " << trial;
    const Eigen::Matrix<double, 6, 3> b3 = random(6, 3);
    const Eigen::Matrix<double, 6, 3> x3 = lu.solve(b3);
    EXPECT_LT((a * x3 - b3).norm(), 100.0 * kEps * a.norm() * x3.norm()) << "trial " << trial;
  }
}

/// BodyLu (a vehicle body's step: the Schur complement of a diagonal translational block) on the matrices of
/// that step: A = M + K with M a mass matrix about an origin off the centre of gravity (translational block
/// m I plus diagonal added mass, coupling blocks -+m S(r_G), rotational block I_G - m S(r_G)^2 plus added
/// inertia, all random: masses 1 kg to 5 t, |r_G| up to 0.5 m) plus, in turn, a diagonal damping h D, or a
/// skew-symmetric K of the Coriolis form (zero translational block; off-diagonal and rotational blocks up to
/// 10x M's norm: a fast turn). The same bounds as PositiveRealLu's (backward stable without pivoting, Golub and
/// Van Loan 2013, sec. 4.4.4): residual within 100 eps |A| |x|, and x within kappa(A) 100 eps of Eigen's pivoted
/// LU. Fails with the Schur complement's A21 A11^-1 A12 left out (residual of order |A12|^2 / A11 |x|).
TEST(BodyLu, SolvesAVehicleBodysStep)
{
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto skew = [](const Eigen::Vector3d& a)
  {
    Eigen::Matrix3d s;
    s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return s;
  };
  const auto vector = [&]() { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  constexpr double kEps = 2.220446049250313e-16;
  for (int trial = 0; trial < 300; ++trial)
  {
    const double mass = std::pow(10.0, 1.85 * (u(rng) + 1.0));  // 1 kg to 5 t
    const Eigen::Vector3d r_g = 0.5 * vector() / std::sqrt(3.0);
    const Eigen::Vector3d inertia = mass * (0.02 + 0.01 * (vector().array() + 1.0)).matrix();
    const Eigen::Vector3d added = mass * (0.5 + 0.5 * vector().array()).matrix();
    const Eigen::Vector3d added_inertia = inertia.cwiseProduct((0.5 + 0.5 * vector().array()).matrix());
    Matrix6 m;
    m.topLeftCorner<3, 3>() = Eigen::Matrix3d((Eigen::Vector3d::Constant(mass) + added).asDiagonal());
    m.topRightCorner<3, 3>() = -mass * skew(r_g);
    m.bottomLeftCorner<3, 3>() = mass * skew(r_g);
    m.bottomRightCorner<3, 3>() =
        Eigen::Matrix3d((inertia + added_inertia).asDiagonal()) - mass * skew(r_g) * skew(r_g);
    Matrix6 k = Matrix6::Zero();
    if (trial % 3 == 0)
    {
      Eigen::Matrix<double, 6, 1> damping;
      for (int i = 0; i < 6; ++i)
      {
        damping[i] = 0.5 * (u(rng) + 1.0) * m.norm();
      }
      k = damping.asDiagonal();
    }
    else
    {
      const Eigen::Matrix3d coupling = skew(vector());
      const Eigen::Matrix3d turning = skew(vector());
      k.topRightCorner<3, 3>() = coupling;
      k.bottomLeftCorner<3, 3>() = coupling;  // -S^T = S: the block pair of C(nu) = [0, -S(p1); -S(p1), -S(p2)]
      k.bottomRightCorner<3, 3>() = turning;
      k *= 10.0 * u(rng) * m.norm() / k.norm();
    }
    const Matrix6 a = m + k;
    BodyLu lu;
    lu.compute(a);
    const Eigen::Matrix<double, 6, 1> b = randomMatrix(rng, 6, 1);
    const Eigen::Matrix<double, 6, 3> b3 = randomMatrix(rng, 6, 3);
    const Eigen::Matrix<double, 6, 1> x = lu.solve(b);
    EXPECT_LT((a * x - b).norm(), 100.0 * kEps * a.norm() * x.norm()) << "trial " << trial;
    const Eigen::Matrix<double, 6, 1> pivoted = a.partialPivLu().solve(b);
    const double kappa = a.norm() * a.inverse().norm();
    EXPECT_LT((x - pivoted).norm(), 100.0 * kEps * kappa * pivoted.norm()) << "trial " << trial;
    const Eigen::Matrix<double, 6, 3> x3 = lu.solve(b3);
    EXPECT_LT((a * x3 - b3).norm(), 100.0 * kEps * a.norm() * x3.norm()) << "trial " << trial;
  }
}

/// BodyLu's two shortcuts for a body whose mass matrix is diagonal (origin at the centre of gravity):
/// computeDiagonal(d) for M + h D = diag(d), and computeGyroscopic(d1^-1, d2, p, q) for M + h/2 C = [diag(d1), -S(p);
/// -S(p), diag(d2) - S(q)], each checked by its residual against the matrix it stands for, built in full (the
/// bound of SolvesAVehicleBodysStep: 100 eps |A| |x|), and against compute() of that matrix, which they must
/// match bit for bit (they do its operations, less the additions of zeros: a vehicle's step is the same with
/// them). One object is reused across the forms in the order diagonal, general, diagonal, gyroscopic, so a
/// shortcut's state left behind by the one before (the diagonal flag) fails it too. Fails with a sign of S(p) or
/// S(q) turned, or with the diagonal flag outliving a later compute() or computeGyroscopic().
TEST(BodyLu, ShortcutsForADiagonalMassSolveTheMatricesTheyStandFor)
{
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  std::mt19937 rng(25);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto minus_skew = [](const Eigen::Vector3d& a)
  {
    Eigen::Matrix3d s;
    s << 0.0, a.z(), -a.y(), -a.z(), 0.0, a.x(), a.y(), -a.x(), 0.0;
    return s;
  };
  constexpr double kEps = 2.220446049250313e-16;
  BodyLu lu;
  for (int trial = 0; trial < 300; ++trial)
  {
    const double mass = std::pow(10.0, 1.85 * (u(rng) + 1.0));  // 1 kg to 5 t
    Vector6 d;
    for (int i = 0; i < 6; ++i)
    {
      d[i] = mass * (i < 3 ? 1.0 + 0.5 * (u(rng) + 1.0) : 0.02 + 0.02 * (u(rng) + 1.0));
    }
    Matrix6 a = Matrix6(d.asDiagonal());
    constexpr int kForms[4] = {0, 2, 0, 1};  // every change of form to and from the diagonal one
    const int form = kForms[trial % 4];
    if (form == 0)
    {
      lu.computeDiagonal(d);
    }
    else
    {
      const Eigen::Vector3d p = 10.0 * mass * Eigen::Vector3d(u(rng), u(rng), u(rng));  // a fast turn
      const Eigen::Vector3d q = 0.5 * mass * Eigen::Vector3d(u(rng), u(rng), u(rng));
      a.topRightCorner<3, 3>() = minus_skew(p);
      a.bottomLeftCorner<3, 3>() = minus_skew(p);
      a.bottomRightCorner<3, 3>() += minus_skew(q);
      if (form == 1)
      {
        lu.computeGyroscopic(d.head<3>().cwiseInverse(), d.tail<3>(), p, q);
      }
      else
      {
        lu.compute(a);  // the general form, after a diagonal shortcut two trials before
      }
    }
    const Vector6 b = randomMatrix(rng, 6, 1);
    const Vector6 x = lu.solve(b);
    EXPECT_LT((a * x - b).norm(), 100.0 * kEps * a.norm() * x.norm()) << "trial " << trial << ", form " << form;
    const Eigen::Matrix<double, 6, 3> b3 = randomMatrix(rng, 6, 3);
    const Eigen::Matrix<double, 6, 3> x3 = lu.solve(b3);
    EXPECT_LT((a * x3 - b3).norm(), 100.0 * kEps * a.norm() * x3.norm()) << "trial " << trial << ", form " << form;
    if (form != 2)
    {
      BodyLu general;
      general.compute(a);
      EXPECT_EQ(x, general.solve(b)) << "trial " << trial << ", form " << form;
    }
  }
}

}  // namespace
}  // namespace rov_tether::test
