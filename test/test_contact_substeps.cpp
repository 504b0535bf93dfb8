// ContactSubstepPolicy and StepMotion (rov_tether/core/contact_substeps.hpp): how many sub-steps a step with
// contact takes, checked against the rules the class states, on numbers alone. The cable is 2 cm thick (the
// default diameter): a particle may move 0.8 x 1 cm = 8 mm in a sub-step, and the pull-in aimed at is
// 5% of 2 cm = 1 mm.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "rov_tether/core/contact_substeps.hpp"

namespace rov_tether::test
{
namespace
{

using Policy = ContactSubstepPolicy;
constexpr double kDiameter = 0.02;
constexpr double kAllowed = Policy::kMotionShareOfRadius * 0.5 * kDiameter;  ///< 8 mm per sub-step [m].
constexpr double kAimed = Policy::kAimedPullInShare * kDiameter;             ///< 1 mm [m].

/// The sub-steps the policy asks for after a step of `taken` sub-steps that moved `motion` and pulled the
/// cable `depth` into a contact, with `substeps` configured.
int after(int taken, double motion, double depth, int substeps)
{
  Policy policy;
  policy.tookStep(taken);
  policy.sawPullIn(depth);
  policy.plan(motion, kDiameter, substeps);
  return policy.substeps(substeps);
}

}  // namespace

// The motion rule alone (no pull-in, after a step of one sub-step): the fewest sub-steps in which the
// fastest particle moves at most 0.8 of the radius in each.
TEST(ContactSubstepPolicy, CutsAStepSoNoParticleMovesMoreThanItsShareOfTheRadiusInOne)
{
  for (const double motion : {0.0, 0.001, 0.0079, 0.0081, 0.05, 0.1, 0.3, 0.5})
  {
    const int n = after(1, motion, 0.0, 1);
    EXPECT_LE(motion / n, kAllowed) << motion << " m in " << n;
    if (n > 1)
    {
      EXPECT_GT(motion / (n - 1), kAllowed) << motion << " m: " << n - 1 << " would do";
    }
  }
  EXPECT_EQ(after(1, 0.05, 0.0, 1), 7);  // 50 mm / 8 mm = 6.25
}

// Never fewer than `substeps`; never more than kMaxSubsteps (unless `substeps` asks for more), nor more than
// kDepthFactor times what the motion and `substeps` ask.
TEST(ContactSubstepPolicy, NeverFewerThanSubstepsNorMoreThanItsCaps)
{
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const int substeps : {1, 2, 5, 16, 70})
  {
    for (const int taken : {1, 3, 20, 64})
    {
      for (const double motion : {0.0, 1e-4, 0.01, 0.1, 0.6, 10.0, inf, nan})
      {
        for (const double depth : {0.0, 1e-4, 1e-3, 1e-2, 1.0, 100.0})
        {
          const int n = after(taken, motion, depth, substeps);
          const std::string at = "substeps " + std::to_string(substeps) + ", taken " + std::to_string(taken) +
                                 ", motion " + std::to_string(motion) + ", depth " + std::to_string(depth);
          EXPECT_GE(n, substeps) << at;
          EXPECT_LE(n, std::max(substeps, Policy::kMaxSubsteps)) << at;
          if (motion < kAllowed * Policy::kMaxSubsteps)
          {
            const int for_motion = std::max(substeps, static_cast<int>(std::ceil(motion / kAllowed)));
            EXPECT_LE(n, std::max(substeps, Policy::kDepthFactor * for_motion)) << at;
          }
        }
      }
    }
  }
}

// The depth rule: the pull-in grows as h^2, so after `taken` sub-steps that pulled `depth` in, the count
// rises to taken x sqrt(depth / aimed), and no further than kDepthFactor times what the motion asks.
TEST(ContactSubstepPolicy, RisesWithThePullInAsItsSquareRoot)
{
  const double motion = 0.035;  // 4.4 x 8 mm: the motion asks 5, the depth rule at most 20
  EXPECT_EQ(after(3, motion, 0.0, 1), 5);
  EXPECT_EQ(after(3, motion, 3.8 * kAimed, 1), 6);    // 3 x 1.95 = 5.8
  EXPECT_EQ(after(3, motion, 15.0 * kAimed, 1), 12);  // 3 x 3.87 = 11.6
  EXPECT_EQ(after(3, motion, 100.0 * kAimed, 1), 4 * 5);
  int previous = 0;
  for (double depth = 0.0; depth < 0.2; depth += 1e-4)
  {
    const int n = after(3, motion, depth, 1);
    EXPECT_GE(n, previous) << "depth " << depth;
    previous = n;
  }
  // The deepest of the step's sub-steps counts.
  Policy policy;
  policy.tookStep(3);
  policy.sawPullIn(15.0 * kAimed);
  policy.sawPullIn(1.0 * kAimed);
  policy.plan(motion, kDiameter, 1);
  EXPECT_EQ(policy.substeps(1), 12);
}

// Falling, the count steps down one a step (so it does not swing between two values), and only while the
// pull predicted for one fewer stays below the aim; each plan() starts the pull-in afresh.
TEST(ContactSubstepPolicy, FallsOneAStepOnceThePullInIsGone)
{
  const double motion = 0.02;  // 2.5 x 8 mm: the motion asks 3, the depth rule at most 12
  Policy policy;
  policy.tookStep(12);
  policy.sawPullIn(100.0 * kAimed);
  policy.plan(motion, kDiameter, 1);
  int n = policy.substeps(1);
  EXPECT_EQ(n, 12);
  for (int expected = 11; expected >= 3; --expected)
  {
    policy.tookStep(n);
    policy.plan(motion, kDiameter, 1);  // no pull-in seen in this step
    n = policy.substeps(1);
    EXPECT_EQ(n, expected);
  }
  policy.tookStep(n);
  policy.plan(motion, kDiameter, 1);
  EXPECT_EQ(policy.substeps(1), 3);                 // what the motion asks
  EXPECT_EQ(after(6, motion, 0.9 * kAimed, 1), 6);  // one fewer would pull 0.9 x (6/5)^2 = 1.3 x the aim: held
}

// A step with a non-finite motion (a failed step) asks for nothing beyond `substeps`; a finite motion beyond
// kMaxSubsteps sub-steps' worth asks for the most; restart() forgets what the last step asked.
TEST(ContactSubstepPolicy, AFailedStepAsksForNoneAndRestartForgets)
{
  Policy policy;
  policy.tookStep(1);
  policy.plan(std::numeric_limits<double>::infinity(), kDiameter, 2);
  EXPECT_EQ(policy.substeps(2), 2);
  EXPECT_EQ(policy.lastMotion(), 0.0);
  policy.plan(1.0, kDiameter, 2);  // 1 m: 125 sub-steps of 8 mm
  EXPECT_EQ(policy.substeps(2), Policy::kMaxSubsteps);
  EXPECT_EQ(policy.lastMotion(), 1.0);
  policy.restart();
  EXPECT_EQ(policy.substeps(2), 2);
}

// StepMotion: the fastest free particle's displacement since start(); particles paid out during the step and
// the outlet (before and after) are not motion.
TEST(StepMotion, MeasuresTheFastestFreeParticleButNotTheSpoolsOwn)
{
  Cable cable;
  cable.resize(10);
  cable.first = 3;
  StepMotion motion;
  motion.start(cable);
  EXPECT_EQ(motion.fastest(cable), 0.0);
  cable.x[6] += 0.3, cable.y[6] += 0.4;  // 0.5 m
  cable.z[8] -= 0.1;
  EXPECT_DOUBLE_EQ(motion.fastest(cable), 0.5);

  // Paid out: particles 1 and 2 left the drum, 3 was the outlet; reeled in: the outlet went from 3 to 5.
  for (const std::size_t first_after : {std::size_t{1}, std::size_t{5}})
  {
    cable.resize(10);
    cable.first = 3;
    motion.start(cable);
    cable.first = first_after;
    for (std::size_t i = 0; i <= std::max<std::size_t>(first_after, 3); ++i)
    {
      cable.x[i] += 2.0;
    }
    EXPECT_EQ(motion.fastest(cable), 0.0) << "outlet " << first_after;
    cable.y[6] += 0.2;
    EXPECT_DOUBLE_EQ(motion.fastest(cable), 0.2) << "outlet " << first_after;
  }
}

}  // namespace rov_tether::test
