// The paper's experiments (Figs. 4, 9/10, 11), reproducibility and step independence.
#include <cstdio>

#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

/// Largest mean stretch over a run of the Fig. 4 scenario (a 10 m cable swept through the water).
double maxStretchFig4(int iterations, SolverType solver = SolverType::kPbd)
{
  Scenario scenario = shippedScenario("paper_fig4_iterations");
  scenario.params.iterations = iterations;
  scenario.params.solver = solver;
  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  double worst = 0.0;
  for (int k = 1; k <= 120; ++k)
  {
    EXPECT_TRUE(succeeded(driver.advanceTo(sim, 0.05 * k)));
    worst = std::max(worst, meanStretch(sim));
  }
  return worst;
}

// Paper Fig. 4: more solver iterations keep the cable closer to its length.
TEST(PaperFig4, LengthIsBetterKeptWithMoreIterations)
{
  const double one = maxStretchFig4(1);
  const double five = maxStretchFig4(5);
  const double ten = maxStretchFig4(10);
  const double fifty = maxStretchFig4(50);
  std::printf("[ measured ] Fig. 4 max mean stretch: 1 it %.4f, 5 it %.4f, 10 it %.4f, 50 it %.5f\n", one, five, ten,
              fifty);
  EXPECT_GT(one, five);
  EXPECT_GT(five, ten);
  EXPECT_GT(ten, fifty);
  // PBD stretch falls roughly as 1 / iterations (docs/references.md, "Where methods fail").
  EXPECT_GT(one, 4.0 * ten);
  EXPECT_LT(ten, 0.02);  // the paper's setting keeps the cable within 2% of its length
}

// The red-black ordering (vectorised) must not give up the convergence of the paper's sequential sweep.
TEST(PaperFig4, RedBlackOrderConvergesLikeTheSequentialSweep)
{
  for (int iterations : {1, 10, 50})
  {
    const double red_black = maxStretchFig4(iterations, SolverType::kPbd);
    const double sequential = maxStretchFig4(iterations, SolverType::kPbdSequential);
    std::printf("[ measured ] %d iterations: red-black %.5f, sequential %.5f\n", iterations, red_black, sequential);
    EXPECT_LT(red_black, 1.5 * sequential) << iterations << " iterations";
  }
}

/// The paper's 2D experiment (docs/references.md) without noise, with the given drag.
Scenario paper2d(double drag, double noise = 0.0)
{
  Scenario scenario = shippedScenario("paper_2d_experiment");
  scenario.params.drag = drag;
  scenario.params.noise = noise;
  return scenario;
}

/// How far the far half of the cable (next to the pinned end) travels between t0 and t1 [m], summed
/// over particles and steps of 0.02 s.
double farHalfTravel(double drag, double t0, double t1)
{
  const Scenario scenario = paper2d(drag);
  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  EXPECT_TRUE(succeeded(driver.advanceTo(sim, t0)));
  std::vector<Position> before = positions(sim);
  double travel = 0.0;
  for (double t = t0 + 0.02; t <= t1 + 1e-9; t += 0.02)
  {
    EXPECT_TRUE(succeeded(driver.advanceTo(sim, t)));
    const std::vector<Position> now = positions(sim);
    for (std::size_t k = 0; k < now.size() / 2; ++k)  // k = 0 is the pinned end (the spool)
    {
      travel += (now[k] - before[k]).norm();
    }
    before = now;
  }
  return travel;
}

// Paper Figs. 9 and 10: damping absorbs the wave; with drag 0.9 the disturbance stays local.
TEST(PaperFig10, DampingKeepsTheDisturbanceLocal)
{
  const double undamped = farHalfTravel(1.0, 0.0, 4.0);
  const double notebook = farHalfTravel(0.98, 0.0, 4.0);
  const double underwater = farHalfTravel(0.9, 0.0, 4.0);
  std::printf("[ measured ] far-half travel over 4 s: drag 1.0 %.3f m, 0.98 %.3f m, 0.9 %.3f m\n", undamped, notebook,
              underwater);
  EXPECT_GT(undamped, notebook);
  EXPECT_GT(notebook, underwater);
  EXPECT_LT(underwater, 0.25 * undamped);
}

// Paper Fig. 9: after the end stops, an undamped cable keeps moving; a damped one comes to rest.
TEST(PaperFig9, WaveEnergyDecaysWithDamping)
{
  const double undamped_late = farHalfTravel(1.0, 4.0, 8.0);
  const double damped_late = farHalfTravel(0.9, 4.0, 8.0);
  std::printf("[ measured ] far-half travel 4-8 s: drag 1.0 %.4f m, 0.9 %.6f m\n", undamped_late, damped_late);
  EXPECT_LT(damped_late, 0.01 * undamped_late);
}

/// RMS change of the cable's shape between t = 8 s and t = 16 s of the 2D experiment [m].
double shapeChangeLate(double noise, bool bending)
{
  Scenario scenario = paper2d(0.9, noise);
  scenario.params.bending = bending;
  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  EXPECT_TRUE(succeeded(driver.advanceTo(sim, 8.0)));
  const std::vector<Position> settled = positions(sim);
  EXPECT_TRUE(succeeded(driver.advanceTo(sim, 16.0)));
  return rmsDistance(settled, positions(sim));
}

// Paper Fig. 11: random micro-current displacements make the cable "lose the memory" of its shape;
// without them it freezes. The freeze needs bending off (see the next test).
TEST(PaperFig11, NoiseMakesTheShapeLoseItsMemory)
{
  const double with_noise = shapeChangeLate(0.0005, false);
  const double without = shapeChangeLate(0.0, false);
  std::printf("[ measured ] RMS shape change 8-16 s: noise %.4f m, no noise %.2e m\n", with_noise, without);
  EXPECT_GT(with_noise, 0.01);
  EXPECT_LT(without, 1e-4);
}

// A known limitation (docs/limitations.md), pinned: the (i, i+2) bending constraints cannot all be met in a slack
// cable, so Gauss-Seidel keeps moving it by centimetres per 8 s without any noise, while the same cable
// without them freezes (1e-11 m, above). When this fails the limitation is gone: update docs/limitations.md and the
// README.
TEST(PaperFig11, BendingConstraintsMakeASlackCableCreepWithoutNoise)
{
  const double bending_creep = shapeChangeLate(0.0, true);
  const double frozen = shapeChangeLate(0.0, false);
  std::printf("[ measured ] RMS shape change 8-16 s without noise: bending on %.4f m, off %.2e m\n", bending_creep,
              frozen);
  EXPECT_GT(bending_creep, 0.01);  // "a few cm per 8 s"
  EXPECT_GT(bending_creep, 1e6 * frozen);
}

TEST(Reproducibility, SameSeedGivesIdenticalRuns)
{
  const Scenario scenario = shippedScenario("spool_payout");
  const Tether a = runTo(scenario, 12.0);
  const Tether b = runTo(scenario, 12.0);
  ASSERT_EQ(a.deployedParticleCount(), b.deployedParticleCount());
  EXPECT_EQ(a.deployedLength(), b.deployedLength());
  for (std::size_t k = 0; k < a.deployedParticleCount(); ++k)
  {
    EXPECT_EQ(a.particle(k), b.particle(k)) << "particle " << k;
  }
}

TEST(Reproducibility, DifferentSeedsGiveDifferentRuns)
{
  Scenario scenario = shippedScenario("paper_2d_experiment");
  const Tether a = runTo(scenario, 4.0);
  scenario.params.seed = 2;
  const Tether b = runTo(scenario, 4.0);
  EXPECT_GT(rmsDistance(positions(a), positions(b)), 1e-4);
}

/// Shape of the paper's 2D experiment at time t for a given internal step, with 50 iterations and
/// bending off so that PBD's own step-dependent stiffness (docs/references.md) stays out of the comparison.
/// `naive` applies the paper's drag 0.9 per step whatever the step (eq. 6 taken literally).
std::vector<Position> paper2dShape(double time_step, bool naive, double t)
{
  Scenario scenario = paper2d(0.9);
  scenario.params.time_step = time_step;
  scenario.params.iterations = 50;
  scenario.params.bending = false;
  if (naive)
  {
    scenario.params.drag = std::pow(0.9, kReferenceStep / time_step);  // per-step factor 0.9
  }
  return positions(runTo(scenario, t));
}

// The same motion at the paper's step (20 ms) and at 5 ms gives nearly the same cable, because drag is
// a rate; taking the paper's drag per step makes the 5 ms run four times as damped.
TEST(StepIndependence, DragAsARateGivesTheSameMotionAtDifferentSteps)
{
  for (double t : {1.0, 4.0})
  {
    const std::vector<Position> reference = paper2dShape(0.02, false, t);
    const double mapped = rmsDistance(reference, paper2dShape(0.005, false, t));
    const double naive = rmsDistance(reference, paper2dShape(0.005, true, t));
    std::printf("[ measured ] t = %.1f s, RMS difference 20 ms vs 5 ms: drag as rate %.4f m, per step %.4f m\n", t,
                mapped, naive);
    EXPECT_LT(mapped, 0.08);
    EXPECT_LT(mapped, 0.2 * naive);
  }
}

/// A heavy cable released horizontally from the spool swings down; its shape at time t [m].
std::vector<Position> swingShape(double time_step, bool naive, double t)
{
  TetherParams params;
  params.noise = 0.0;
  params.time_step = time_step;
  params.bending = false;
  params.iterations = 20;
  params.weight_in_water = 0.5;
  params.winch_mode = WinchMode::kLocked;
  params.initial_deployed_length = 5.0;
  if (naive)
  {
    params.drag = std::pow(0.9, kReferenceStep / time_step);
  }
  Tether sim(params, Position::Zero(), Position(4.9, 0.0, 0.0));
  sim.detachVehicle();
  EXPECT_TRUE(succeeded(sim.advance(t)));
  return positions(sim);
}

TEST(StepIndependence, HeavyCableSwingsTheSameAtDifferentSteps)
{
  const double mapped = rmsDistance(swingShape(0.02, false, 2.0), swingShape(0.005, false, 2.0));
  const double naive = rmsDistance(swingShape(0.02, false, 2.0), swingShape(0.005, true, 2.0));
  std::printf("[ measured ] swing at 2 s, 20 ms vs 5 ms: drag as rate %.4f m, per step %.4f m\n", mapped, naive);
  EXPECT_LT(mapped, 0.1);
  EXPECT_LT(mapped, 0.2 * naive);
}

/// Mean squared displacement of the free particles of a floating cable over `duration` under noise
/// alone, averaged over seeds [m^2].
double noiseSpread(double time_step, double duration, int substeps = 1)
{
  double sum = 0.0;
  int count = 0;
  for (std::int64_t seed = 1; seed <= 8; ++seed)
  {
    TetherParams params;
    params.time_step = time_step;
    params.substeps = substeps;
    params.seed = seed;
    params.noise = 0.002;
    params.bending = false;
    params.winch_mode = WinchMode::kLocked;
    params.initial_deployed_length = 4.0;
    Tether sim(params, Position::Zero(), Position(3.0, 0.0, 0.0));
    const std::vector<Position> start = positions(sim);
    EXPECT_TRUE(succeeded(sim.advance(duration)));
    const std::vector<Position> end = positions(sim);
    for (std::size_t k = 5; k + 5 < start.size(); ++k)
    {
      sum += (end[k] - start[k]).squaredNorm();
      ++count;
    }
  }
  return sum / count;
}

// The random displacement is scaled with the step so its long-term effect does not depend on it.
TEST(StepIndependence, NoiseSpreadDoesNotDependOnTheStep)
{
  const double fine = noiseSpread(0.005, 5.0);
  const double coarse = noiseSpread(0.02, 5.0);
  std::printf("[ measured ] noise spread over 5 s: dt 5 ms %.3e m^2, dt 20 ms %.3e m^2 (ratio %.2f)\n", fine, coarse,
              fine / coarse);
  EXPECT_GT(fine / coarse, 0.6);
  EXPECT_LT(fine / coarse, 1.6);
}

// Sub-steps are steps too: the noise is added in every sub-step with that sub-step's amplitude, so the
// spread does not grow with `substeps` (it grew 3.3x, 10.6x and 23.9x at 2, 4 and 8 sub-steps when the
// whole step's noise went into one sub-step). The band is the step test's above: 8 seeds of a random walk,
// whose spread scatters by some 20% from seed set to seed set; [0.6, 1.6] is wide enough for that and far
// below the 3.3x the old bug gave at 2 sub-steps.
TEST(StepIndependence, NoiseSpreadDoesNotDependOnTheSubsteps)
{
  const double one = noiseSpread(0.02, 5.0, 1);
  for (int substeps : {2, 4, 8})
  {
    const double many = noiseSpread(0.02, 5.0, substeps);
    std::printf("[ measured ] noise spread over 5 s at 20 ms: %d sub-steps / 1 = %.2f\n", substeps, many / one);
    EXPECT_GT(many / one, 0.6) << substeps;
    EXPECT_LT(many / one, 1.6) << substeps;
  }
}

}  // namespace
}  // namespace rov_tether::test
