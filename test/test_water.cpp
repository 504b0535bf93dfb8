// The water: Morison drag (docs/references.md "Straight cable under axial drag"), added mass (the hanging
// chain's period in water), the current and its slow variation, the seabed, and what a scene skips.
#include <cstdio>

#include "rov_tether/study/study.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

// T(s) = R_t (L - s): 100 m at 1 m/s carries 25.8 N at the anchor, for every method.
TEST(Morison, AxialDragOnAStraightCable)
{
  for (SolverType solver : {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass})
  {
    TetherParams p = study::findCase("axial_drag").base(50);
    p.solver = solver;
    p.iterations = 20;
    p.substeps = solver == SolverType::kLumpedMass ? 10 : 1;
    const study::Result r = study::findCase("axial_drag").run(p);
    std::printf("[ measured ] axial drag, %s, 50 segments: anchor tension %.3f%% off R_t (L - dL/2)\n",
                toString(solver).c_str(), 100 * r.tension_error);
    EXPECT_FALSE(r.failed);
    EXPECT_LT(r.tension_error, 0.02) << toString(solver);
  }
}

/// Force of the water on the cable computed independently from the final shape: Morison drag of a
/// cable at rest in a uniform current [N].
Force dragOnCableAtRest(const Tether& sim, const Position& current)
{
  const TetherParams& p = sim.params();
  Force total = Force::Zero();
  for (std::size_t k = 0; k + 1 < sim.deployedParticleCount(); ++k)
  {
    const Position d = sim.particle(k + 1) - sim.particle(k);
    const Position t = d.normalized();
    const double length = sim.state().rest[sim.state().first + k];
    const Position along = current.dot(t) * t;
    const Position across = current - along;
    total += 0.5 * p.water_density * p.diameter * length *
             (p.normal_drag_coefficient * across.norm() * across +
              p.tangential_drag_coefficient * kPi * along.norm() * along);
  }
  return total;
}

// A cable held at both ends across a current: at rest, the supports hold exactly the water's drag.
// The drag computed here from the final shape (per segment) and the tensions the simulation reports
// (per particle) agree within 2%.
TEST(Morison, SupportsBalanceTheCrossFlowDrag)
{
  TetherParams p;
  p.solver = SolverType::kXpbd;
  p.iterations = 30;
  p.cable_length = 12.0;
  p.segment_length = 0.25;
  p.initial_deployed_length = 12.0;
  p.winch_mode = WinchMode::kLocked;
  p.noise = 0.0;
  p.bending = false;
  p.drag_model = DragModel::kMorison;
  p.current = {0.0, 0.3, 0.0};
  Tether sim(p, Position::Zero(), Position(10.0, 0.0, 0.0));
  ASSERT_TRUE(succeeded(sim.advance(60.0)));
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  const std::size_t last = sim.deployedParticleCount() - 1;
  // The pulls of the cable on its supports (the spool segment's tension along it, the vehicle force)
  // are what the supports resist: at rest they add up to the drag.
  const Force on_supports = tensions.front() * (sim.particle(1) - sim.particle(0)).normalized() + sim.vehicleForce();
  const Force drag = dragOnCableAtRest(sim, Position(0.0, 0.3, 0.0));
  std::printf(
      "[ measured ] cross flow 0.3 m/s: supports hold %.4f N, drag from the shape %.4f N (middle at y = %.3f)\n",
      on_supports.y(), drag.y(), sim.particle(last / 2).y());
  EXPECT_GT(sim.particle(last / 2).y(), 0.5) << "the current bends the cable downstream";
  EXPECT_NEAR(on_supports.y(), drag.y(), 0.02 * drag.y());
  EXPECT_NEAR(on_supports.x(), 0.0, 0.02 * drag.y());
}

/// Period of the free end's swing of a chain hanging in still water [s].
double swingPeriod(double added_mass_coefficient, SolverType solver)
{
  TetherParams p = study::findCase("hanging_chain").base(20);
  p.drag_model = DragModel::kMorison;
  p.diameter = 0.1;
  p.weight_in_water = 90.0;
  p.added_mass_coefficient = added_mass_coefficient;
  p.solver = solver;
  p.iterations = 20;
  p.current = {0.3, 0.0, 0.0};
  Tether sim(p, Position::Zero());
  EXPECT_TRUE(succeeded(sim.advance(10.0)));
  // Released from the current's push, without drag, so the swing keeps its period.
  p.current = {0.0, 0.0, 0.0};
  p.normal_drag_coefficient = p.tangential_drag_coefficient = 0.0;
  EXPECT_TRUE(succeeded(sim.setParams(p)));
  const std::size_t end = sim.deployedParticleCount() - 1;
  std::vector<double> crossings;
  double last = sim.particle(end).x();
  for (int k = 0; k < 4000; ++k)
  {
    sim.step();
    const double x = sim.particle(end).x();
    if (last < 0.0 && x >= 0.0)
    {
      crossings.push_back(sim.time() - p.time_step * x / (x - last));
    }
    last = x;
  }
  EXPECT_GE(crossings.size(), 3u);
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

// docs/references.md: in water replace g by w / (mu + C_a rho A). With C_a = 1 and d = 0.1 m the added
// mass is 8.05 kg/m on 1 kg/m of cable, so the chain swings sqrt(9.05) = 3.0x slower.
TEST(Morison, AddedMassSlowsTheHangingChainAsPublished)
{
  auto reference = [](double mass)
  {
    const double g = 90.0 / mass;
    return 2.0 * kPi / (2.4048 / 2.0 * std::sqrt(g / 10.0));
  };
  const double added = 1.0 + 1025.0 * kPi * 0.01 / 4.0;
  for (SolverType solver : {SolverType::kXpbd, SolverType::kDirect})
  {
    const double with = swingPeriod(1.0, solver);
    const double without = swingPeriod(0.0, solver);
    std::printf(
        "[ measured ] %s, hanging chain in water: T1 %.3f s with added mass (ref %.3f), %.3f s without (ref %.3f)\n",
        toString(solver).c_str(), with, reference(added), without, reference(1.0));
    EXPECT_NEAR(with / reference(added), 1.0, 0.02) << toString(solver);
    EXPECT_NEAR(without / reference(1.0), 1.0, 0.02) << toString(solver);
  }
}

// Morison's added mass acts across the cable only (C_a is a normal coefficient): pulled along its length
// the cable accelerates only its own mass. A free cable hanging from the spool (neutrally buoyant, no drag,
// d = 2 cm: 0.322 kg/m added on 0.1 kg/m) is lifted by its spool at a = 0.5 m/s^2; by momentum, the spool's
// tension averaged over the pull is mu L a = 0.5 N, where an isotropic added mass would give
// (mu + mu_a) L a = 2.11 N. (The spool outlet particle's own half segment hangs on the spool: mu (L - dL / 2)
// a = 0.4975 N.) Each method, within 2%: the average over 1.5 s of an axial ringing that no drag damps
// (its period is 4 L / sqrt(EA / mu) = 40 ms), and pbd's stretch, which its iteration count sets, grows a
// little during the pull, so its centre of mass follows the spool a little late.
TEST(Morison, AddedMassActsAcrossTheCableOnly)
{
  for (SolverType solver : {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kDirect})
  {
    TetherParams p;
    p.solver = solver;
    p.drag_model = DragModel::kMorison;
    p.normal_drag_coefficient = p.tangential_drag_coefficient = 0.0;
    p.noise = 0.0;
    p.bending = false;
    p.winch_mode = WinchMode::kLocked;
    p.initial_deployed_length = p.cable_length;
    p.iterations = 50;
    // The spool moves once a step, so one sub-step; lumped_mass at half its critical step, which the
    // cable's own (along) mass sets: dL / sqrt(EA / mu) = 0.1 ms.
    p.time_step = solver == SolverType::kLumpedMass ? 0.5 * p.criticalStep() : 0.005;
    Tether sim(p, Position::Zero());
    const double a = 0.5;
    double impulse = 0.0;
    const double start = 0.5;
    while (sim.time() < 2.0 - 1e-9)
    {
      const double t = sim.time() + p.time_step;
      ASSERT_TRUE(succeeded(sim.setSpoolPosition(Position(0.0, 0.0, 0.5 * a * t * t))));
      sim.step();
      if (t > start + 1e-9)
      {
        impulse += sim.summary().tension_spool * p.time_step;  // the spool's pull over the step
      }
    }
    const double mean = impulse / (2.0 - start);
    const double expected = p.mass_per_length * (p.cable_length - 0.5 * p.segment_length) * a;
    std::printf("[ measured ] %s: spool tension while lifting at %.1f m/s^2: %.4f N (mu L a = %.4f N)\n",
                toString(solver).c_str(), a, mean, expected);
    EXPECT_NEAR(mean, expected, 0.02 * expected) << toString(solver);
  }
}

// The current's variation: seeded, of the stated RMS, smooth in space and time (no high-frequency
// content, as the paper's conclusion asks).
TEST(Current, SlowSpatiallyCorrelatedVariation)
{
  TetherParams p;
  p.current = {0.2, 0.0, 0.0};
  p.current_variation = 0.1;
  const Tether a(p, Position::Zero());
  const Tether b(p, Position::Zero());
  p.seed = 2;
  const Tether c(p, Position::Zero());
  double sum_squares = 0.0;
  double worst_space = 0.0, worst_time = 0.0;
  int count = 0;
  Xoshiro256Plus rng(7);
  for (int k = 0; k < 2000; ++k)
  {
    const Position point(100.0 * rng.symmetric(), 100.0 * rng.symmetric(), 20.0 * rng.symmetric());
    const double t = 600.0 * (1.0 + rng.symmetric());
    const Position u = a.currentAt(point, t);
    EXPECT_EQ(u, b.currentAt(point, t));
    sum_squares += (u - Position(0.2, 0.0, 0.0)).squaredNorm();
    ++count;
    worst_space = std::max(worst_space, (a.currentAt(point + Position(1.0, 0.0, 0.0), t) - u).norm());
    worst_time = std::max(worst_time, (a.currentAt(point, t + 1.0) - u).norm());
  }
  const double rms = std::sqrt(sum_squares / count);
  std::printf("[ measured ] current variation: RMS %.4f m/s (set 0.1), largest change over 1 m %.4f, over 1 s %.4f\n",
              rms, worst_space, worst_time);
  EXPECT_NEAR(rms, 0.1, 0.02);
  EXPECT_LT(worst_space, 0.02);  // a fifth of the amplitude: wavelengths of 20-100 m
  EXPECT_LT(worst_time, 0.02);   // periods of 1-5 min: at most 0.1 sqrt(1/2) 4 (2 pi / 60 s) = 0.03 m/s^2
  EXPECT_NE(a.currentAt(Position::Zero(), 0.0), c.currentAt(Position::Zero(), 0.0)) << "the seed matters";
}

// With the paper's damping the cable relaxes towards the water's velocity: a free cable in a uniform
// current streams downstream of its spool.
TEST(Current, CableStreamsDownstream)
{
  for (DragModel model : {DragModel::kDamping, DragModel::kMorison})
  {
    TetherParams p;
    p.drag_model = model;
    p.current = {0.5, 0.0, 0.0};
    p.noise = 0.0;
    p.initial_deployed_length = 5.0;
    p.winch_mode = WinchMode::kLocked;
    Tether sim(p, Position::Zero());
    ASSERT_TRUE(succeeded(sim.advance(60.0)));
    const Position end = sim.particle(sim.deployedParticleCount() - 1);
    std::printf("[ measured ] %s, 0.5 m/s current: free end at (%.3f, %.3f, %.3f)\n", toString(model).c_str(), end.x(),
                end.y(), end.z());
    EXPECT_GT(end.x(), 0.9 * sim.deployedLength()) << toString(model);
  }
}

// The seabed: a heavy slack cable lies on it, and friction holds it against a sideways current that
// slides it when the seabed is frictionless. That no particle ends below the bed is how the contact is
// built (it is projected last), so it is not what this test checks. What the contact must get right is
// the load it takes: the part of the cable off the bed is a catenary that touches down with zero slope,
// and along a catenary T = H + w y, y the height above that touchdown (docs/references.md). The spool's
// segment carries the tension of its middle, y = 0.95 m above the bed (the spool is 1 m above it), so
// its tension exceeds its horizontal part by the weight of 0.95 m of cable, 1.9 N. Without the bed's
// support the 20 m cable would hang about 8 m deep between its ends 10 m apart (T - H near 16 N).
TEST(Seabed, ContactAndFriction)
{
  auto lay = [](double friction, double* lowest, double* vertical_excess, double* w_y)
  {
    TetherParams p;
    p.cable_length = 20.0;
    p.initial_deployed_length = 20.0;
    p.winch_mode = WinchMode::kLocked;
    p.noise = 0.0;
    p.weight_in_water = 2.0;
    p.seabed_z = -6.0;
    p.seabed_friction = friction;
    p.bending = false;  // the chain alone: the readout is then the stretch constraint's force
    Tether sim(p, Position(0.0, 0.0, -5.0), Position(10.0, 0.0, -5.0));
    EXPECT_TRUE(succeeded(sim.advance(10.0)));
    const TetherSummary settled = sim.summary();
    const Position first = (sim.particle(1) - sim.particle(0)).normalized();
    const double horizontal = settled.tension_spool * std::hypot(first.x(), first.y());
    *vertical_excess = settled.tension_spool - horizontal;
    *w_y = p.weight_in_water * (0.5 * (sim.particle(0).z() + sim.particle(1).z()) - p.seabed_z);
    const double before = sim.particle(sim.deployedParticleCount() / 2).y();
    p.current = {0.0, 0.2, 0.0};
    EXPECT_TRUE(succeeded(sim.setParams(p)));
    *lowest = 0.0;
    for (int k = 0; k < 100; ++k)
    {
      EXPECT_TRUE(succeeded(sim.advance(0.05)));
      for (std::size_t i = 0; i < sim.deployedParticleCount(); ++i)
      {
        *lowest = std::min(*lowest, sim.particle(i).z());
      }
    }
    return sim.particle(sim.deployedParticleCount() / 2).y() - before;
  };
  double lowest_free = 0.0, lowest_held = 0.0, excess_free = 0.0, excess_held = 0.0, w_y_free = 0.0, w_y_held = 0.0;
  const double slide_free = lay(0.0, &lowest_free, &excess_free, &w_y_free);
  const double slide_held = lay(1.0, &lowest_held, &excess_held, &w_y_held);
  std::printf(
      "[ measured ] seabed: T - H at the spool %.3f N frictionless (w y %.3f N), %.3f N with friction 1 (w y %.3f N); "
      "middle slides %.3f m frictionless, %.4f m with friction 1; lowest z %.6f m\n",
      excess_free, w_y_free, excess_held, w_y_held, slide_free, slide_held, std::min(lowest_free, lowest_held));
  // Within half a segment's weight, w dL / 2 = 0.1 N: where the chain of lumped masses meets the bed, the
  // particle that touches down is carried partly by the bed and partly by the cable.
  const double half_segment_weight = 0.5 * 2.0 * 0.1;
  EXPECT_NEAR(excess_free, w_y_free, half_segment_weight);
  EXPECT_NEAR(excess_held, w_y_held, half_segment_weight);
  EXPECT_GT(slide_free, 0.5);
  EXPECT_LT(slide_held, 0.1 * slide_free);
}

// Particles on the spool are not part of the scene: no drag, current or weight moves them.
TEST(Skips, ParticlesOnTheSpoolAreNeverTouched)
{
  TetherParams p;
  p.drag_model = DragModel::kMorison;
  p.current = {0.3, 0.1, 0.0};
  p.current_variation = 0.2;
  p.weight_in_water = 1.0;
  const Position spool(1.0, 2.0, 3.0);
  Tether sim(p, spool, Position(3.0, 2.0, 2.0));
  ASSERT_TRUE(succeeded(sim.advance(5.0)));
  const Cable& s = sim.state();
  ASSERT_GT(s.first, 10u);
  for (std::size_t i = 0; i < s.first; ++i)
  {
    EXPECT_EQ(s.position(i), spool) << i;
    EXPECT_EQ(Position(s.px[i], s.py[i], s.pz[i]), spool) << i;
  }
}

}  // namespace
}  // namespace rov_tether::test
