// The direct solver's primal path, its terms against their definitions (src/core/direct_primal.hpp): the step
// energy (energyTerms), which its Armijo line search compares before and after a Newton step: each segment's term
// must be the integral of the force law the step solves for, or the line search would accept steps that do not
// lower the true energy and halve ones that do; and the bending joints' constant Hessian terms (bendingRows).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "direct_primal.hpp"

namespace
{

using rov_tether::EnergyLaw;
using rov_tether::PrimalNewton;

/// One segment's law as DirectWorkspace::begin makes it (its comment derives it): Kelvin-Voigt with backward
/// Euler, alpha = L / (EA h^2 + BA h); for a cable slack at the step's start (stretch s0 < 0) the dashpot's
/// middle piece from its zero (1 - share) s0 up to the kink -share s0, share = BA / (h EA + BA).
struct Law
{
  double alpha, kink, zero, dashpot;
};

Law slackDampedSegment(double rest, double ea, double ba, double h, double start)
{
  const double share = ba / (h * ea + ba);
  return {rest / (ea * h * h + ba * h), -share * start, start * (1.0 - share), ba * h / rest};
}

/// The force (multiplier) the law gives at stretch c, written from its definition: above the kink the spring
/// max(C, 0) / alpha, on the middle piece kink / alpha + dashpot (C - kink) down to its zero, 0 below; a rod's
/// (two-sided) C / alpha.
double force(const Law& law, double c, bool unilateral)
{
  if (!unilateral)
  {
    return c / law.alpha;
  }
  if (c >= law.kink)
  {
    return std::max(c, 0.0) / law.alpha;
  }
  return c > law.zero ? law.kink / law.alpha + law.dashpot * (c - law.kink) : 0.0;
}

/// Each stretch's potential energy (half energyTerms' elastic term) for one law, through energyTerms with
/// every particle pinned (no kinetic term) and no bending.
std::vector<double> potentials(const Law& law, const std::vector<double>& stretch, bool unilateral)
{
  const std::size_t m = stretch.size();
  const std::vector<double> zeros(m + 4, 0.0);  // also the (unread) curvatures, offset by 2
  const std::vector<double> alpha(m, law.alpha), kink(m, law.kink), zero(m, law.zero), dashpot(m, law.dashpot);
  const PrimalNewton::Particles pinned{zeros.data(), zeros.data(), zeros.data(), zeros.data(),
                                       zeros.data(), zeros.data(), zeros.data(), zeros.data(),
                                       zeros.data(), nullptr,      nullptr,      nullptr};
  const EnergyLaw energy_law{stretch.data(), alpha.data(),   kink.data(),
                             zero.data(),    dashpot.data(), {zeros.data(), zeros.data(), zeros.data()},
                             zeros.data()};
  const std::size_t stride = m + 1;
  std::vector<double> terms(4 * stride, -1.0);
  rov_tether::energyTerms(pinned, energy_law, m, false, unilateral, false, terms.data(), stride);
  for (std::size_t l = 0; l <= m; ++l)
  {
    EXPECT_EQ(terms[l], 0.0) << "a pinned particle has no kinetic term";
  }
  std::vector<double> out(m);
  for (std::size_t k = 0; k < m; ++k)
  {
    out[k] = 0.5 * terms[2 * stride + k];
  }
  return out;
}

/// d/dC of the potential by central differences at each stretch in `at`, with step `delta`.
std::vector<double> slopes(const Law& law, const std::vector<double>& at, double delta, bool unilateral)
{
  std::vector<double> stretch;
  for (double c : at)
  {
    stretch.push_back(c + delta);
    stretch.push_back(c - delta);
  }
  const std::vector<double> e = potentials(law, stretch, unilateral);
  std::vector<double> out;
  for (std::size_t i = 0; i < at.size(); ++i)
  {
    out.push_back((e[2 * i] - e[2 * i + 1]) / (2.0 * delta));
  }
  return out;
}

// Each piece of the law is linear in C, so its integral is quadratic and a central difference gives its
// slope exactly but for rounding: the potential's slope must be the law's force on every piece (a line
// search on any other energy would accept the wrong steps). The stretches are chosen at least 10 delta from
// the pieces' ends. Rounding: the potential's scale E ~ F^2 alpha over 2 delta, a few 1e-16 relative; the
// bound 1e-6 of the largest force leaves that a factor of about 1e5.
TEST(StepEnergy, EachSegmentsSlopeIsItsLawsForce)
{
  // A 0.1 m segment of EA 1e4 N and BA 100 N s at h = 5 ms, slack by 1 cm at the step's start.
  const Law damped = slackDampedSegment(0.1, 1e4, 100.0, 0.005, -0.01);
  ASSERT_GT(damped.kink, 0.0);
  ASSERT_LT(damped.zero, 0.0);
  ASSERT_NEAR(force(damped, damped.zero + 1e-12, true), 0.0, 1e-9) << "the middle piece reaches 0 at its zero";
  const Law cable{damped.alpha, 0.0, 0.0, 0.0};  // no dashpot: max(C, 0) / alpha
  const double delta = 1e-7;
  const double span = 0.02;
  struct Case
  {
    const char* name;
    Law law;
    bool unilateral;
    std::vector<double> at;
  };
  const std::vector<Case> cases = {
      {"damped, above the kink", damped, true, {damped.kink + 1e-4, 0.01, span}},
      {"damped, on the middle piece",
       damped,
       true,
       {0.5 * (damped.kink + damped.zero), 0.0 + 1e-5, damped.zero + 1e-5}},
      {"damped, below its zero", damped, true, {damped.zero - 1e-4, -span}},
      {"cable, taut", cable, true, {1e-5, 0.01, span}},
      {"cable, slack", cable, true, {-1e-5, -span}},
      {"rod, stretched", cable, false, {1e-5, span}},
      {"rod, compressed", cable, false, {-1e-5, -span}},
  };
  const double largest = span / cable.alpha + damped.kink / damped.alpha;
  for (const Case& c : cases)
  {
    const std::vector<double> s = slopes(c.law, c.at, delta, c.unilateral);
    for (std::size_t i = 0; i < c.at.size(); ++i)
    {
      EXPECT_NEAR(s[i], force(c.law, c.at[i], c.unilateral), 1e-6 * largest) << c.name << " at C = " << c.at[i];
    }
  }
}

// The potential is continuous where the law changes piece (the line search compares energies across them):
// at the kink and at the middle piece's zero a step of 2 eps changes it by at most 2 eps times the larger
// force there (the mean value theorem on each side). Below the zero the force is 0, so the potential is the
// same constant all the way down: the middle piece's at its zero, 0 but for the rounding of the force there
// (a few ulps of kink / alpha, squared, over twice the dashpot).
TEST(StepEnergy, TheSegmentsPotentialIsContinuousAcrossItsLawsPieces)
{
  const Law damped = slackDampedSegment(0.1, 1e4, 100.0, 0.005, -0.01);
  const double eps = 1e-9;
  const std::vector<double> e =
      potentials(damped, {damped.kink - eps, damped.kink + eps, damped.zero - eps, damped.zero + eps, -1.0}, true);
  const double at_kink = damped.kink / damped.alpha;
  EXPECT_LE(std::abs(e[1] - e[0]), 2.0 * eps * at_kink * (1.0 + 1e-6)) << "a jump at the kink";
  EXPECT_GT(e[1], 0.0);
  const double rounding = 1e-15 * at_kink;
  EXPECT_LE(e[2], 0.5 * rounding * rounding / damped.dashpot) << "below where the dashpot's force is 0, no energy";
  EXPECT_EQ(e[4], e[2]) << "no slope below the zero";
  EXPECT_LE(std::abs(e[3] - e[2]), 2.0 * eps * force(damped, damped.zero + eps, true) + 1e-30) << "a jump at the zero";
}

// The kinetic terms: (x - x~)^T M (x - x~) with M = m_across I + (m_along - m_across) t t^T (the added mass acts
// across the cable only), split into its two parts, and none for a pinned particle; each joint's bending term
// |kappa|^2 / gamma. Closed forms at hand-picked numbers.
TEST(StepEnergy, KineticAndBendingTermsAreTheirQuadraticForms)
{
  // Three particles, the middle one pinned (its mass and added mass set, to show they are not counted); two
  // segments; one joint.
  const std::vector<double> w = {1.0, 0.0, 2.0}, mass = {2.0, 3.0, 0.5}, less = {-0.5, -1.0, -0.25};
  const std::vector<double> x = {1.0, 5.0, 0.5}, y = {2.0, 5.0, -1.0}, z = {0.0, 5.0, 2.0};
  const std::vector<double> xt = {0.5, 0.0, 0.0}, yt = {2.0, 0.0, 0.0}, zt = {1.0, 0.0, 0.0};
  const std::vector<double> tx = {1.0, 1.0, 0.0}, ty = {0.0, 0.0, 0.6}, tz = {0.0, 0.0, 0.8};
  const PrimalNewton::Particles p{w.data(),  mass.data(), less.data(), x.data(),  y.data(),  z.data(),
                                  xt.data(), yt.data(),   zt.data(),   tx.data(), ty.data(), tz.data()};
  const std::vector<double> c = {0.0, 0.0}, alpha = {1.0, 1.0}, none = {0.0, 0.0};
  const std::vector<double> curve_x = {0.0, 0.0, 0.3, 0.0}, curve_y = {0.0, 0.0, -0.4, 0.0};
  const std::vector<double> curve_z = {0.0, 0.0, 1.2, 0.0}, inv_gamma = {4.0};
  const EnergyLaw law{c.data(),        alpha.data(), none.data(),
                      none.data(),     none.data(),  {curve_x.data(), curve_y.data(), curve_z.data()},
                      inv_gamma.data()};
  const std::size_t stride = 3;
  std::vector<double> terms(4 * stride, -1.0);
  rov_tether::energyTerms(p, law, 2, true, true, true, terms.data(), stride);
  // Particle 0: d = (0.5, 0, -1), |d|^2 = 1.25, d.t = 0.5; particle 2: d = (0.5, -1, 2), |d|^2 = 5.25, d.t = 1.
  EXPECT_DOUBLE_EQ(terms[0], 2.0 * 1.25);
  EXPECT_EQ(terms[1], 0.0) << "pinned";
  EXPECT_DOUBLE_EQ(terms[2], 0.5 * 5.25);
  EXPECT_DOUBLE_EQ(terms[stride + 0], -0.5 * 0.25);
  EXPECT_EQ(terms[stride + 1], 0.0) << "pinned";
  EXPECT_DOUBLE_EQ(terms[stride + 2], -0.25 * 1.0);
  EXPECT_DOUBLE_EQ(terms[3 * stride], (0.09 + 0.16 + 1.44) * 4.0);
  // Without added mass (`along` false: a loop of its own) the same kinetic terms across, none pinned, and the
  // lengthwise ones not written.
  std::vector<double> isotropic(4 * stride, -1.0);
  rov_tether::energyTerms(p, law, 2, false, true, true, isotropic.data(), stride);
  EXPECT_DOUBLE_EQ(isotropic[0], 2.0 * 1.25);
  EXPECT_EQ(isotropic[1], 0.0) << "pinned";
  EXPECT_DOUBLE_EQ(isotropic[2], 0.5 * 5.25);
  EXPECT_EQ(isotropic[stride + 0], -1.0) << "not written without added mass";
  EXPECT_DOUBLE_EQ(isotropic[3 * stride], (0.09 + 0.16 + 1.44) * 4.0);
}

// The bending joints' Hessian terms of the rows bendingRows writes (those with all three joints), against the
// curvature's definition: joint j's curvature C_j = a x_j - (a + b) x_j+1 + b x_j+2 (a, b the inverse rest
// lengths of its segments) is linear, so its energy |C_j|^2 / (2 gamma_j) has the constant Hessian
// g_p g_q / gamma_j (times I) between its particles p, q with weights g. Rest lengths all different (with
// equal ones, a and b of neighbouring joints could be swapped unseen), a hinge (1 / gamma = 0) and a pinned
// particle (its rows and columns 0). Each product is a few roundings: 1e-14 relative.
TEST(BendingRows, EachRowsTermsAreTheJointsHessian)
{
  const std::size_t m = 9;  // segments; particles 0..9, joints 0..7
  const std::vector<double> rest = {0.07, 0.11, 0.09, 0.13, 0.08, 0.12, 0.1, 0.095, 0.105};
  std::vector<double> inv_rest, inv_gamma = {3.0, 0.5, 2.0, 0.0, 1.5, 4.0, 0.75, 2.5};
  for (double r : rest)
  {
    inv_rest.push_back(1.0 / r);
  }
  std::vector<double> w(m + 1, 1.0);
  w[6] = 0.0;  // pinned
  const std::size_t n = m + 1;
  std::vector<double> pull(3 * n, NAN), diag(n, NAN), first(2 * n, NAN), second(n, NAN);
  const rov_tether::BendingRows rows{
      w.data(),    inv_rest.data(),        inv_gamma.data(), {&pull[0], &pull[n], &pull[2 * n]},
      diag.data(), {&first[0], &first[n]}, second.data()};
  const std::size_t from = 2, to = m - 1;
  rov_tether::bendingRows(rows, from, to);
  // Particle p's weight in joint j (0 unless j <= p <= j + 2).
  auto g = [&](std::size_t j, std::size_t p)
  {
    const double a = inv_rest[j], b = inv_rest[j + 1];
    return p == j ? a : p == j + 1 ? -(a + b) : p == j + 2 ? b : 0.0;
  };
  auto near = [](double got, double want) { EXPECT_NEAR(got, want, 1e-14 * std::max(1.0, std::abs(want))); };
  for (std::size_t l = 0; l <= m; ++l)
  {
    SCOPED_TRACE("row " + std::to_string(l));
    if (l < from || l >= to)
    {
      for (std::size_t i = 0; i < 3; ++i)
      {
        EXPECT_TRUE(std::isnan(pull[i * n + l])) << "not its row";
      }
      EXPECT_TRUE(std::isnan(diag[l])) << "not its row";
      EXPECT_TRUE(std::isnan(first[l]) && std::isnan(first[n + l]) && std::isnan(second[l])) << "not its row";
      continue;
    }
    const bool free_l = w[l] > 0.0;
    double sum = 0.0;  // the diagonal block's terms of the row's joints
    for (std::size_t i = 0; i < 3; ++i)
    {
      const std::size_t j = l - 2 + i;  // the row's joints in order: l - 2, l - 1, l
      near(pull[i * n + l], free_l ? g(j, l) * inv_gamma[j] : 0.0);
      sum += free_l ? g(j, l) * g(j, l) * inv_gamma[j] : 0.0;
    }
    near(diag[l], sum);
    // The block (l + 1, l): from joints l - 1 and l; the block (l + 2, l): from joint l.
    const bool pair = free_l && w[l + 1] > 0.0;
    near(first[l], pair ? g(l - 1, l + 1) * g(l - 1, l) * inv_gamma[l - 1] : 0.0);
    near(first[n + l], pair ? g(l, l + 1) * g(l, l) * inv_gamma[l] : 0.0);
    near(second[l], free_l && w[l + 2] > 0.0 ? g(l, l + 2) * g(l, l) * inv_gamma[l] : 0.0);
  }
}

}  // namespace
