// End forces (issue 24): what the spool and the vehicle receive from a heavy cable, against the closed-form
// end reactions of its catenary. docs/references.md, "End forces of a heavy catenary".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/study/study.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

// A heavy jumper-like cable (410 N/m in water, EA 5e8 N; 100 m between level supports 80 m apart) in coarse
// 2.5 m segments, at rest. A continuous catenary's supports each carry H horizontally and half its weight,
// w L / 2, vertically; the discrete chain's end segments carry that less the half segment of weight lumped
// at the end particle, w dL / 2 = 2.5% of V here, which the support holds too. The end forces
// (spoolForce(), vehicleForce()) must match H and w L / 2 within 0.1% (the bound; the chain's own
// discretisation moves H by O((dL / L)^2), measured below), where the end segments' tensions miss the
// support tension T(0) by about w dL / 2 x V / T(0).
constexpr double kLength = 100.0, kSpan = 80.0, kWeight = 410.0, kStiffness = 5e8;

TetherParams heavyCable()
{
  TetherParams p;
  p.cable_length = kLength;
  p.segment_length = 2.5;
  p.initial_deployed_length = kLength;
  p.min_deployed_length = p.segment_length;
  p.winch_mode = WinchMode::kLocked;
  p.noise = 0.0;
  p.bending = false;
  p.weight_in_water = kWeight;
  p.mass_per_length = 50.0;
  p.axial_stiffness = kStiffness;
  return p;
}

study::Catenary heavyCatenary()
{
  study::Catenary reference;
  reference.length = kLength;
  reference.weight = kWeight;
  reference.stiffness = kStiffness;
  EXPECT_TRUE(reference.solve(kSpan));
  return reference;
}

TEST(EndForces, HeavyCatenaryEndsCarryTheClosedFormReactions)
{
  Tether sim(heavyCable(), Position::Zero(), Position(kSpan, 0.0, 0.0));
  ASSERT_TRUE(sim.advance(60.0).ok);
  const study::Catenary reference = heavyCatenary();
  const double h = reference.horizontal, v = 0.5 * kWeight * kLength;
  const Force spool = sim.spoolForce(), vehicle = sim.vehicleForce();
  const TetherSummary s = sim.summary();
  const double support = reference.tension(0.0);
  std::printf(
      "[ measured ] heavy catenary, 2.5 m segments: H %.2f N, V %.2f N; spool (%.2f, %.2f, %.2f) N, "
      "vehicle (%.2f, %.2f, %.2f) N; end segments %.2f / %.2f N against T(0) %.2f N (%+.2f%%)\n",
      h, v, spool.x(), spool.y(), spool.z(), vehicle.x(), vehicle.y(), vehicle.z(), s.tension_spool, s.tension_vehicle,
      support, 100.0 * (s.tension_spool / support - 1.0));
  // The supports pull the cable up and outwards, so the cable pulls the spool towards the vehicle (+x) and
  // the vehicle back (-x), and both down.
  EXPECT_NEAR(spool.x(), h, 1e-3 * h);
  EXPECT_NEAR(vehicle.x(), -h, 1e-3 * h);
  EXPECT_NEAR(spool.z(), -v, 1e-3 * v);
  EXPECT_NEAR(vehicle.z(), -v, 1e-3 * v);
  EXPECT_NEAR(spool.y(), 0.0, 1e-9 * v);
  EXPECT_EQ(s.spool_force, spool);
  EXPECT_EQ(s.vehicle_force, vehicle);
  // The segment tensions stay what they are, the axial force inside the end segments: the support's reaction
  // less the half segment of weight lumped at the end particle, |(H, V - w dL / 2)| (dL the end segment's rest
  // length), within the same 0.1%; the next segment in would be 1 dL further from it (23490 N against 24325 N).
  const Cable& cable = sim.state();
  const double spool_segment = std::hypot(h, v - 0.5 * kWeight * cable.rest[cable.first]);
  const double vehicle_segment = std::hypot(h, v - 0.5 * kWeight * cable.rest[cable.size() - 2]);
  EXPECT_NEAR(s.tension_spool, spool_segment, 1e-3 * spool_segment);
  EXPECT_NEAR(s.tension_vehicle, vehicle_segment, 1e-3 * vehicle_segment);
  EXPECT_LT(s.tension_spool, support * (1.0 - 1e-3));
}

// A dynamic vehicle carries the half segment at its end as a kinematic one does: the same catenary hung
// from a body too heavy to move much (1e9 kg, neutrally buoyant, its damping scaled alike: it drifts a few mm
// in the minute; heavier, the pull, M (x - x~) / h^2, would lose digits to rounding: 4% at 1e12 kg), which
// the step couples in, pulls it with the closed-form reaction within 0.1%. Without the half segment's
// weight its vertical pull would be 2.5% short.
TEST(EndForces, ADynamicVehicleCarriesItsHalfSegment)
{
  VehicleParams heavy;  // the BlueROV2 Heavy with every mass, inertia and damping scaled up alike
  const double scale = 1e9 / heavy.mass;
  heavy.mass *= scale;
  heavy.inertia *= scale;
  heavy.added_mass *= scale;
  heavy.linear_damping *= scale;
  heavy.quadratic_damping *= scale;
  heavy.displaced_volume = heavy.mass / heavy.water_density;
  VehicleBody body;
  ASSERT_TRUE(body.setParams(heavy).ok);
  ASSERT_TRUE(body.setState({kSpan, 0.0, 0.0}, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  Tether sim(heavyCable(), Position::Zero());
  const Status attached = sim.attachVehicleBody(body, Eigen::Vector3d::Zero());
  ASSERT_TRUE(attached.ok) << attached.message;
  ASSERT_TRUE(sim.advance(60.0).ok);
  const study::Catenary reference = heavyCatenary();
  const double h = reference.horizontal, v = 0.5 * kWeight * kLength;
  const Force pull = sim.vehicleForce();
  std::printf(
      "[ measured ] heavy catenary from a 1e9 kg vehicle: pull (%.2f, %.2f, %.2f) N against (%.2f, 0, %.2f) N; "
      "the vehicle moved %.2g m\n",
      pull.x(), pull.y(), pull.z(), -h, -v,
      (sim.particle(sim.deployedParticleCount() - 1) - Position(kSpan, 0.0, 0.0)).norm());
  EXPECT_NEAR(pull.x(), -h, 1e-3 * h);
  EXPECT_NEAR(pull.z(), -v, 1e-3 * v);
  EXPECT_EQ(sim.summary().vehicle_force, pull);
}

// A cable cannot push: a pbd cable (bilateral constraints) driven back along itself at 5 m/s carries
// compression in its end segments, which neither end receives; each still carries its half segment's weight
// in water, exactly. Both ends' pushes left in, the vehicle would be pushed away along the cable.
TEST(EndForces, ACompressedEndSegmentPushesNeitherEnd)
{
  TetherParams p;
  p.noise = 0.0;
  p.solver = SolverType::kPbd;
  p.winch_mode = WinchMode::kLocked;
  p.initial_deployed_length = 3.0;
  p.weight_in_water = 2.0;
  Tether sim(p, Position::Zero(), Position(3.0, 0.0, 0.0));  // straight and taut along x
  for (int k = 1; k <= 20; ++k)
  {
    ASSERT_TRUE(sim.addVehicleSample(0.01 * k, Position(3.0 - 0.05 * k, 0.0, 0.0)).ok);
  }
  bool compressed = false;
  for (int k = 0; k < 20 && !compressed; ++k)
  {
    sim.step();
    const TetherSummary s = sim.summary();
    compressed = s.tension_vehicle < -0.1 && s.tension_spool < -0.1;
  }
  ASSERT_TRUE(compressed) << "the end segments never carried compression together";
  const double dl = sim.state().rest[sim.state().size() - 2];
  EXPECT_EQ(sim.vehicleForce(), Force(0.0, 0.0, -0.5 * p.weight_in_water * dl));
  EXPECT_EQ(sim.spoolForce(), Force(0.0, 0.0, -0.5 * p.weight_in_water * sim.state().rest[sim.state().first]));
}

}  // namespace
}  // namespace rov_tether::test
