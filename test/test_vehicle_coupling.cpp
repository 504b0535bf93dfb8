// A dynamic vehicle coupled into the `direct` solver's implicit step (VehicleCoupling, Tether::attachVehicleBody;
// issue 25). Each bound says where it comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "rov_tether/core/vehicle_coupling.hpp"
#include "rov_tether/core/world.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kLength = 10.0;  // [m] deployed, locked
constexpr double kThrust = 40.0;  // [N] surge, away from the spool

/// A neutrally buoyant tether without noise on a locked winch, `kLength` deployed, default step (0.005 s) and
/// default bending stiffness (EI 0.2 N m^2: a rod, the primal path) unless `cable` (EI 0: a cable, which
/// carries no compression).
TetherParams lockedTether(double axial_stiffness, bool cable = false)
{
  TetherParams p;
  p.solver = SolverType::kDirect;
  p.winch_mode = WinchMode::kLocked;
  p.cable_length = kLength;
  p.initial_deployed_length = kLength;
  p.axial_stiffness = axial_stiffness;
  p.noise = 0.0;
  p.weight_in_water = 0.0;
  if (cable)
  {
    p.bending_stiffness = 0.0;
  }
  return p;
}

/// The BlueROV2 Heavy (the defaults, 13.5 kg), made neutrally buoyant so that only the tether holds it.
VehicleParams blueRov()
{
  VehicleParams v;
  v.displaced_volume = v.mass / v.water_density;
  return v;
}

/// A 1 kg vehicle: the BlueROV2 with every mass, inertia, added mass and damping divided by 13.5 (the same
/// decay rate c / 2m'), neutrally buoyant: the light end of issue 25's mass ratios (1 kg to 5 t).
VehicleParams oneKilogram()
{
  VehicleParams v = blueRov();
  const double scale = 1.0 / v.mass;
  v.mass = 1.0;
  v.displaced_volume = v.mass / v.water_density;
  v.inertia *= scale;
  v.added_mass *= scale;
  v.linear_damping *= scale;
  v.quadratic_damping *= scale;
  return v;
}

/// A 5 t work-class vehicle: config/vehicles/work_class_example.yaml (2916 kg) with every mass, added mass
/// and inertia scaled by 5000 / 2916 (the same shape, denser), neutrally buoyant; its damping kept.
VehicleParams workClass()
{
  VehicleParams v;
  const double scale = 5000.0 / 2916.0;
  v.mass = 5000.0;
  v.water_density = 1025.0;
  v.displaced_volume = v.mass / v.water_density;
  v.inertia = Eigen::Vector3d(2022.0, 1788.0, 2877.0) * scale;
  v.center_of_buoyancy = Eigen::Vector3d(0.0, 0.0, 0.06);
  v.added_mass << 1374.0, 1538.0, 4035.0, 1470.0, 1050.0, 1726.0;
  v.added_mass *= scale;
  v.linear_damping << 1208.0, 0.0, 2910.0, 0.0, 2540.0, 0.0;
  v.quadratic_damping << 5076.0, 7812.0, 6840.0, 9253.0, 3655.0, 11664.0;
  v.thrust_limit << 24560.0, 24560.0, 34730.0, 45490.0, 25010.0, 39400.0;
  return v;
}

/// A body at rest, upright, facing +x, its origin `behind` [m] ahead of the attachment point at (x, 0, 0).
VehicleBody bodyAt(const VehicleParams& params, double x, double behind)
{
  VehicleBody body;
  EXPECT_TRUE(body.setParams(params).ok);
  EXPECT_TRUE(body.setState({x + behind, 0.0, 0.0}, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  return body;
}

Wrench surge(double force)
{
  Wrench w = Wrench::Zero();
  w[0] = force;
  return w;
}

/// The tension's swing (max - min) over the last window of a run and over the window before it: a taut stop
/// settles when the last swing is small and no larger than the one before (no growing ringing).
struct TensionSwings
{
  /// `from_end`: steps left after this one; `window`: steps per window.
  void record(int from_end, int window, double tension)
  {
    if (from_end >= 2 * window)
    {
      return;
    }
    const int w = from_end < window ? 1 : 0;  // 0: the window before, 1: the last
    lo[w] = std::min(lo[w], tension);
    hi[w] = std::max(hi[w], tension);
  }
  double last() const { return hi[1] - lo[1]; }
  double before() const { return hi[0] - lo[0]; }
  double lo[2] = {1e300, 1e300};
  double hi[2] = {-1e300, -1e300};
};

struct TautStopCase
{
  double axial_stiffness;  // EA [N]
  VehicleParams vehicle;
  const char* name;
  const char* id;  // the test's name
};

class TautStop : public ::testing::TestWithParam<TautStopCase>
{
};

// A vehicle thrusting F in surge away from the spool on a locked tether of length L, starting at rest with
// the tether straight and unstretched. Physics: it comes to rest where the tether holds it, the tension F all
// along (no weight, no current, nothing moving), each segment stretched by F / EA, so the attachment point
// sits at L (1 + F / EA) from the spool.
//
// How long until it rests: the vehicle of mass m' (with added mass) on the tether's spring k = EA / L rings
// at omega = sqrt(k / m') and its own linear damping c = Xu alone decays the ringing at the rate
// zeta omega = c / (2 m') (independent of k; the water's damping of the tether and the implicit step's
// numerical damping only add to it). The step load F starts a ringing of tension amplitude F; the test runs
// until that bound has decayed it to 0.1% of F (ln 1000 = 6.9 time constants) and then watches two
// windows of 2 s: the tension's peak-to-peak in the last must be within 1% of F and not larger than in the one
// before (no growth). A tether that delayed the stiff force by one step would ring with a growing amplitude
// (the 0 to 600 N) as soon as the delay exceeds c / k: 1.4 ms at EA 1e5 on 10 m, 1.4e-8 s at 1e9.
// Seen failing: with the attachment pinned in the solve and the solved pull applied to the body after it (a
// staggered coupling), every case but the 5 t at EA 1e5 fails (at EA 1e9 the tension swings by 7e7 N); that
// one passes as the criterion says: its delay h = 5 ms is below c / k = 1208 / 1e4 = 0.12 s;
// with the solve's vehicle mass twice the body's (w / 2), the BlueROV2 at EA 1e9 rings to 1e6 N: the mobility
// the solve gives the attachment must be the body's own.
//
// Bounds: tension (at the vehicle: the force the solve applied; at the spool: the segment's multiplier)
// within 1% of F (the issue). Distance: within 1% of the stretch F L / EA plus the solver's tolerance summed
// over the segments (each stops at |C - alpha lambda| <= tolerance x segment length).
TEST_P(TautStop, ThrustOnALockedTetherComesToRestAtTheStretchedLength)
{
  const TautStopCase& c = GetParam();
  const TetherParams params = lockedTether(c.axial_stiffness);
  const double behind = 0.2;  // [m] the attachment 0.2 m behind the body origin, on its x axis: no moment
  Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
  ASSERT_TRUE(tether.attachVehicleBody(bodyAt(c.vehicle, kLength, behind), Eigen::Vector3d(-behind, 0.0, 0.0)).ok);
  ASSERT_TRUE(tether.setVehicleThrust(surge(kThrust)).ok);

  const double mass = c.vehicle.mass + c.vehicle.added_mass[0];
  const double decay_rate = c.vehicle.linear_damping[0] / (2.0 * mass);  // [1/s]
  const double window = 2.0;                                             // [s]
  const double settle = std::log(1000.0) / decay_rate;
  const double dt = params.time_step;
  const auto steps = static_cast<int>(std::ceil((settle + 2.0 * window) / dt));
  const auto window_steps = static_cast<int>(std::lround(window / dt));
  TensionSwings swings;
  for (int i = 0; i < steps; ++i)
  {
    tether.step();
    ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
    swings.record(steps - 1 - i, window_steps, tether.vehicleForce().norm());
  }
  const double last_swing = swings.last();
  const double swing_before = swings.before();
  EXPECT_LT(last_swing, 0.01 * kThrust) << c.name;
  EXPECT_LE(last_swing, swing_before + 1e-9 * kThrust) << c.name << ": the ringing grows";

  const Force pull = tether.vehicleForce();
  EXPECT_NEAR(pull.norm(), kThrust, 0.01 * kThrust) << c.name;
  EXPECT_LT(pull.x(), 0.0) << c.name << ": the tether pulls the vehicle back to the spool";
  EXPECT_NEAR(tether.summary().tension_spool, kThrust, 0.01 * kThrust) << c.name;

  const double stretch = kThrust * kLength / c.axial_stiffness;
  const double segments = static_cast<double>(tether.deployedParticleCount() - 1);
  const double solver_slack = segments * params.solver_tolerance * params.segment_length;
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_NEAR(end.norm(), kLength + stretch, 0.01 * stretch + solver_slack) << c.name;
  // The body is where the attachment point says, and at rest (1 mm/s: the last ringing, 1% of F / sqrt(k m')).
  const VehicleBody& body = *tether.vehicleBody();
  EXPECT_NEAR((body.position() + body.attitude() * Eigen::Vector3d(-behind, 0.0, 0.0) - end).norm(), 0.0, 1e-12);
  EXPECT_LT(body.velocity().head<3>().norm(), 1e-3) << c.name;
}

INSTANTIATE_TEST_SUITE_P(VehicleCoupling, TautStop,
                         ::testing::Values(TautStopCase{1e5, blueRov(), "BlueROV2, EA 1e5", "BlueRov2_EA1e5"},
                                           TautStopCase{1e9, blueRov(), "BlueROV2, EA 1e9", "BlueRov2_EA1e9"},
                                           TautStopCase{1e5, oneKilogram(), "1 kg, EA 1e5", "OneKilogram_EA1e5"},
                                           TautStopCase{1e9, oneKilogram(), "1 kg, EA 1e9", "OneKilogram_EA1e9"},
                                           TautStopCase{1e5, workClass(), "5 t, EA 1e5", "FiveTonnes_EA1e5"},
                                           TautStopCase{1e9, workClass(), "5 t, EA 1e9", "FiveTonnes_EA1e9"}),
                         [](const ::testing::TestParamInfo<TautStopCase>& info) { return std::string(info.param.id); });

// The taut stop with the pull at an angle to the body's axes, where its mobility is not isotropic: the
// BlueROV2 pitched 45 degrees, thrusting 40 N along the world's x (F R^T e_x in its own frame: surge and heave
// alike), attached at its origin, without a restoring moment (r_B = r_G), so at rest nothing turns it.
// Surge and heave differ in mass (19.9 and 32.2 kg with added mass), so a pull along the tether moves the
// attachment point off the tether's line (W_p n not along n): the sideways part the solve's one scalar mass
// leaves to the next step (docs/model.md, "What is approximate"). Physics as in TautStop: at rest at
// L (1 + F / EA) with the tension F (1%), the ringing under 1% of F and not growing; at EA 1e5 and 1e9.
// Run for 30 s: the slowest decay is the heave's, Zw / 2 m' = 0.51 /s, 15 time constants.
// Seen failing (at EA 1e9) with the solve's vehicle mass the isotropic bound (the largest eigenvalue of W_p, the
// lightest direction) instead of the mobility along the tether: the energy test and the BlueROV2 and 1 kg
// TautStop cases fail too.
TEST(VehicleCoupling, TautStopWithThePullAtAnAngleToTheBodyAxes)
{
  for (const double axial_stiffness : {1e5, 1e9})
  {
    SCOPED_TRACE(axial_stiffness);
    const TetherParams params = lockedTether(axial_stiffness);
    VehicleParams vehicle = blueRov();
    vehicle.center_of_buoyancy = vehicle.center_of_gravity;
    VehicleBody body;
    ASSERT_TRUE(body.setParams(vehicle).ok);
    const Eigen::Quaterniond pitched(Eigen::AngleAxisd(0.25 * 3.14159265358979323846, Eigen::Vector3d::UnitY()));
    ASSERT_TRUE(body.setState({kLength, 0.0, 0.0}, pitched, Twist::Zero()).ok);
    Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
    ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d::Zero()).ok);
    Wrench thrust = Wrench::Zero();
    thrust.head<3>() = pitched.conjugate() * Eigen::Vector3d(kThrust, 0.0, 0.0);
    ASSERT_TRUE(tether.setVehicleThrust(thrust).ok);
    const double window = 2.0;
    const auto steps = static_cast<int>(std::lround(30.0 / params.time_step));
    const auto window_steps = static_cast<int>(std::lround(window / params.time_step));
    TensionSwings swings;
    for (int i = 0; i < steps; ++i)
    {
      tether.step();
      ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
      swings.record(steps - 1 - i, window_steps, tether.vehicleForce().norm());
    }
    EXPECT_LT(swings.last(), 0.01 * kThrust);
    EXPECT_LE(swings.last(), swings.before() + 1e-9 * kThrust) << "the ringing grows";
    EXPECT_NEAR(tether.vehicleForce().norm(), kThrust, 0.01 * kThrust);
    const double stretch = kThrust * kLength / axial_stiffness;
    const double segments = static_cast<double>(tether.deployedParticleCount() - 1);
    const double solver_slack = segments * params.solver_tolerance * params.segment_length;
    const Position end = tether.particle(tether.deployedParticleCount() - 1);
    EXPECT_NEAR(end.norm(), kLength + stretch, 0.01 * stretch + solver_slack);
  }
}

/// Closed form of m' u' = -a u - b u|u| from u0 > 0: u(t) = a / ((a / u0 + b) e^{a t / m'} - b).
double surgeDecay(double u0, double a, double b, double m, double t)
{
  return a / ((a / u0 + b) * std::exp(a * t / m) - b);
}

// Free surge decay with the tether slack: the vehicle coasts at u0 = 0.2 m/s towards the spool along a
// straight, unstretched tether without bending stiffness. A cable does not push, so the tether's pull is exactly zero
// and the surge speed obeys m' u' = -Xu u - Xuu u|u| (m' with added mass). It coasts at most (m' / Xuu) ln(1 + Xuu u0 /
// Xu) = 0.157 m, less than two segments, so it never passes the next particle far enough to pull the last segment taut
// the other way. Bound: the body's own scheme, as in VehicleBody.FreeSurgeDecayFollowsTheClosedForm: the implicit
// damping with |u| from the step's start decays no faster than the closed form, and lags it by at most h/2 (a / m') (u0
// - u(t)) (first order in h). Seen failing with a rod (EI 0.2 N m^2, which does push: 19.8 N at the first step).
TEST(VehicleCoupling, FreeSurgeDecayWithASlackTetherFollowsTheClosedForm)
{
  const TetherParams params = lockedTether(1e5, true);
  const VehicleParams vehicle = blueRov();
  Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
  VehicleBody body = bodyAt(vehicle, kLength, 0.2);
  const double u0 = -0.2;  // towards the spool (-x)
  Twist velocity = Twist::Zero();
  velocity[0] = u0;
  ASSERT_TRUE(body.setState(body.position(), body.attitude(), velocity).ok);
  ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d(-0.2, 0.0, 0.0)).ok);

  const double m = vehicle.mass + vehicle.added_mass[0];
  const double a = vehicle.linear_damping[0];
  const double b = vehicle.quadratic_damping[0];
  const double h = params.time_step;
  for (int n = 1; n <= 1000; ++n)
  {
    tether.step();
    ASSERT_EQ(tether.vehicleForce(), Force::Zero()) << "step " << n << ": a slack cable pulled or pushed";
    const double t = n * h;
    const double exact = surgeDecay(-u0, a, b, m, t);
    const double speed = -tether.vehicleBody()->velocity()[0];
    const double bound = 0.5 * h * (a / m) * (-u0 - exact);
    ASSERT_GE(speed - exact, -1e-12) << "t " << t;
    ASSERT_LE(speed - exact, bound + 1e-12) << "t " << t << ": u " << speed << ", closed form " << exact;
  }
  EXPECT_LT(tether.vehicleBody()->velocity().tail<5>().cwiseAbs().maxCoeff(), 1e-12);
}

/// Kinetic energy of the deployed free particles (isotropic masses: the damping drag model) [J].
double cableKineticEnergy(const Tether& tether, double h)
{
  const Cable& cable = tether.state();
  double energy = 0.0;
  for (std::size_t i = cable.first; i < cable.size(); ++i)
  {
    if (cable.inv_mass[i] > 0.0)
    {
      const Position v = (cable.position(i) - Position(cable.px[i], cable.py[i], cable.pz[i])) / h;
      energy += 0.5 * v.squaredNorm() / cable.inv_mass[i];
    }
  }
  return energy;
}

/// Elastic energy of the stretched segments, EA C^2 / (2 L) (a cable: only stretched ones) [J].
double cableElasticEnergy(const Tether& tether)
{
  const Cable& cable = tether.state();
  double energy = 0.0;
  for (std::size_t j = cable.first; j + 1 < cable.size(); ++j)
  {
    const double stretch = std::max(cable.strain(j) * cable.rest[j], 0.0);
    energy += 0.5 * tether.params().axial_stiffness * stretch * stretch / cable.rest[j];
  }
  return energy;
}

void expectEnergyNeverGrows(double axial_stiffness);

// Energy with thrust off, no current, water drag on, a cable (no bending stiffness, so its energy is the
// stretch's alone): the vehicle coasts away from the spool at 1 m/s on an
// unstretched, straight tether, is caught by it, springs back, is caught again. The step is backward Euler in
// the positions of chain and vehicle together (the force at the step's end; the cable's stretch energy
// max(|d| - L, 0)^2 EA / 2L is convex), the water drag and the vehicle's damping only take energy out, and the
// body's Coriolis part keeps it: so the total, vehicle (1/2 nu^T M nu + W z_G - B z_B) plus tether (kinetic
// with v = (x - x_prev) / h, and elastic), must never grow. Bound per step: the work the largest pull can do
// through the solver's residual, T_max x segments x tolerance x segment length (1e-4 J at T 1 kN), against the
// 10 J the vehicle starts with. At EA 1e5 N and 1e9 N (peak pulls about u0 sqrt(k m'): 0.45 kN and 45 kN).
// Seen failing with the staggered coupling (attachment pinned in the solve, the pull applied after it): at
// EA 1e9 the energy jumps from 8.6 J to 7e8 J in the first step.
TEST(VehicleCoupling, EnergyNeverGrowsWithThrustOff)
{
  for (const double axial_stiffness : {1e5, 1e9})
  {
    expectEnergyNeverGrows(axial_stiffness);
  }
}

void expectEnergyNeverGrows(double axial_stiffness)
{
  SCOPED_TRACE(axial_stiffness);
  const TetherParams params = lockedTether(axial_stiffness, true);
  const VehicleParams vehicle = blueRov();
  Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
  ASSERT_FALSE(tether.state().anisotropic);
  VehicleBody body = bodyAt(vehicle, kLength, 0.2);
  Twist velocity = Twist::Zero();
  velocity[0] = 1.0;
  ASSERT_TRUE(body.setState(body.position(), body.attitude(), velocity).ok);
  ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d(-0.2, 0.0, 0.0)).ok);

  const double h = params.time_step;
  auto total = [&]
  {
    const VehicleBody& b = *tether.vehicleBody();
    return b.kineticEnergy() + b.potentialEnergy() + cableKineticEnergy(tether, h) + cableElasticEnergy(tether);
  };
  const double start = total();
  const double segments = static_cast<double>(tether.deployedParticleCount() - 1);
  double before = start;
  double largest_pull = 0.0;
  for (int n = 1; n <= 1000; ++n)
  {
    tether.step();
    ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
    const double pull = tether.vehicleForce().norm();
    largest_pull = std::max(largest_pull, pull);
    const double now = total();
    const double slack = std::max(pull, 1.0) * segments * params.solver_tolerance * params.segment_length;
    ASSERT_LE(now, before + slack) << "step " << n << ": the energy grew from " << before << " J to " << now << " J";
    before = now;
  }
  EXPECT_GT(largest_pull, 100.0) << "the tether never caught the vehicle: the test tested nothing";
  EXPECT_LT(before, 0.5 * start) << "the water should have taken most of the energy in 5 s";
}

// Rotation: the tether's moment about the body origin through the attachment offset turns the vehicle. The
// BlueROV2 (neutral, r_B 0.01 m above r_G) thrusts T = 40 N in surge on a locked 2 m tether attached d below its
// origin, r = (0, 0, -d). At rest the tether must pull opposite the thrust, F = -T R e_x (the tether lines up
// with the body's x axis), so its moment in the body frame is r x (-T e_x) = (0, T d, 0), a constant nose-down
// pitch moment; the restoring moment of the buoyancy at r_B is -B BG sin(theta) (no other moment at rest). So
// the quasi-static pitch is sin(theta) = T d / (B BG), here 0.378 (22 degrees) at d = 12.5 mm. (Yaw has no
// restoring moment, so an angle in closed form is in pitch.) Bound 2% of theta (the issue's). It settles in
// seconds: the pitch rings at sqrt(B BG / (Iy + Mqdot)) = 1.9 rad/s with damping ratio 0.58 (Mq 0.8); the
// tether's line lines up with the body through the heave damping Zw against the tether's sideways stiffness
// T / L, time constant Zw L / T = 1.7 s; 30 s is 18 of those. Seen failing with the moment left out of the
// body's step (theta 0).
TEST(VehicleCoupling, AnOffsetAttachmentPitchesTheVehicleAsItsMomentSays)
{
  const double length = 2.0;
  TetherParams params = lockedTether(1e5);
  params.cable_length = params.initial_deployed_length = length;
  const VehicleParams vehicle = blueRov();
  const double depth = 0.0125;  // d [m]
  Tether tether(params, Position::Zero(), Position(length, 0.0, 0.0));
  VehicleBody body;
  ASSERT_TRUE(body.setParams(vehicle).ok);
  ASSERT_TRUE(body.setState({length, 0.0, depth}, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d(0.0, 0.0, -depth)).ok);
  ASSERT_TRUE(tether.setVehicleThrust(surge(kThrust)).ok);
  for (int i = 0; i < static_cast<int>(std::lround(30.0 / params.time_step)); ++i)
  {
    tether.step();
  }
  ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
  const double restoring = vehicle.buoyancy() * (vehicle.center_of_buoyancy - vehicle.center_of_gravity).z();
  const double expected = std::asin(kThrust * depth / restoring);
  const Eigen::Vector3d forward = tether.vehicleBody()->attitude() * Eigen::Vector3d::UnitX();
  const double pitch = std::asin(-forward.z());  // nose down positive (about +y)
  EXPECT_NEAR(pitch, expected, 0.02 * expected);
  EXPECT_LT(std::abs(forward.y()), 1e-6) << "no yaw: nothing turns the vehicle about z";
  EXPECT_NEAR(tether.vehicleForce().norm(), kThrust, 0.01 * kThrust);
}

// Steady towing: the BlueROV2 thrusting F = 40 N pays the tether out through a brake (brake_tension 5 N, within
// the step through the drum's law). Quasi-steady (the vehicle's time constant m' / (Xu + 2 Xuu U) is 0.14 s,
// the length changes over seconds), the speed U solves
//   F = Xu U + Xuu U^2 + brake_tension + R_t(U) l,
// the tether's axial drag R_t(U) l: with the damping drag model every particle's velocity relative to the
// water decays at gamma = -ln(drag) / kReferenceStep, a force mu gamma U per metre on a cable sliding along
// itself at U. Bound 1% (within the 3%): the sub-step's discrete decay (1 - e^{-gamma h}) / h differs
// from gamma by gamma h / 2 = 1.3% of the tether's part, 0.4% of the total at most, and the tether's part is
// 1-4% of U (at 3 to 10 m), which 3% would not tell from none. The spool end holds the brake's
// tension (1%). Seen failing with the pull left out of the body's step (U 9% fast); the staggered coupling
// passes it (5-7 N on a slowly lengthening tether do not ring: it is the taut stop that tells them apart).
TEST(VehicleCoupling, SteadyTowingThroughABrakeGoesAtTheDragBalanceSpeed)
{
  TetherParams params = lockedTether(1e5);
  params.winch_mode = WinchMode::kBrake;
  params.brake_tension = 5.0;
  params.cable_length = 40.0;
  params.initial_deployed_length = 2.0;
  params.max_winch_speed = 2.0;  // [m/s] above the towing speed: the brake decides, not the winch's limit
  const VehicleParams vehicle = blueRov();
  Tether tether(params, Position::Zero(), Position(2.0, 0.0, 0.0));
  ASSERT_TRUE(tether.attachVehicleBody(bodyAt(vehicle, 2.0, 0.2), Eigen::Vector3d(-0.2, 0.0, 0.0)).ok);
  ASSERT_TRUE(tether.setVehicleThrust(surge(kThrust)).ok);
  const double gamma = -std::log(params.drag) / kReferenceStep;
  const auto steps_per_second = static_cast<int>(std::lround(1.0 / params.time_step));
  double worst = 0.0, without_tether = 0.0;
  for (int second = 1; second <= 20; ++second)
  {
    for (int i = 0; i < steps_per_second; ++i)
    {
      tether.step();
    }
    ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
    if (second < 2)
    {
      continue;  // the start: 14 time constants
    }
    const double l = tether.deployedLength();
    const double linear = vehicle.linear_damping[0] + params.mass_per_length * gamma * l;
    const double quadratic = vehicle.quadratic_damping[0];
    const double rest = params.brake_tension - kThrust;
    const double expected = (-linear + std::sqrt(linear * linear - 4.0 * quadratic * rest)) / (2.0 * quadratic);
    const double speed = tether.vehicleBody()->velocity()[0];
    EXPECT_NEAR(speed, expected, 0.01 * expected) << "t " << tether.time() << " s, deployed " << l << " m";
    worst = std::max(worst, std::abs(speed / expected - 1.0));
    // What the balance without the tether's drag would say: the bound must tell the two apart.
    const double bare = vehicle.linear_damping[0];
    const double without = (-bare + std::sqrt(bare * bare - 4.0 * quadratic * rest)) / (2.0 * quadratic);
    without_tether = std::max(without_tether, std::abs(speed / without - 1.0));
    EXPECT_NEAR(tether.summary().tension_spool, params.brake_tension, 0.01 * params.brake_tension);
  }
  EXPECT_GT(tether.deployedLength(), 10.0) << "the vehicle paid out the tether";
  EXPECT_GT(without_tether, 0.01) << "the premise: the bound tells the tether's drag from none";
  std::printf(
      "[ measured ] towing: speed within %.2f%% of the balance; the balance without the tether's drag up to %.2f%% "
      "off\n",
      100.0 * worst, 100.0 * without_tether);
}

// Only `direct` has an implicit step to couple a vehicle into; the others refuse it, and a solver change away
// from direct is refused while a vehicle is dynamic. Samples are refused while the end is dynamic; thrust
// without a dynamic vehicle is refused; detaching returns to a kinematic end.
TEST(VehicleCoupling, OnlyDirectTakesADynamicVehicleAndBadInputIsRefused)
{
  for (const SolverType solver :
       {SolverType::kPbd, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kPbdSequential})
  {
    TetherParams params = lockedTether(1e5);
    params.solver = solver;
    Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
    const Status refused = tether.attachVehicleBody(bodyAt(blueRov(), kLength, 0.2), Eigen::Vector3d(-0.2, 0.0, 0.0));
    EXPECT_FALSE(refused.ok);
    EXPECT_NE(refused.message.find("direct"), std::string::npos) << refused.message;
    EXPECT_FALSE(tether.vehicleDynamic());
  }
  TetherParams same_water = lockedTether(1e5);
  same_water.water_density = blueRov().water_density;  // or the vehicle floats in other water, and is said to
  Tether tether(same_water, Position::Zero(), Position(kLength, 0.0, 0.0));
  EXPECT_FALSE(tether.setVehicleThrust(surge(kThrust)).ok);
  EXPECT_FALSE(tether.attachVehicleBody(bodyAt(blueRov(), kLength, 0.2), Eigen::Vector3d(NAN, 0.0, 0.0)).ok);
  const Status within = tether.attachVehicleBody(bodyAt(blueRov(), kLength, 0.2), Eigen::Vector3d(-0.2, 0.0, 0.0));
  ASSERT_TRUE(within.ok);
  EXPECT_EQ(within.message, "") << "within the cable's reach, in the same water: nothing to say";
  EXPECT_TRUE(tether.vehicleDynamic());
  EXPECT_FALSE(tether.setVehicleThrust(surge(NAN)).ok);
  EXPECT_FALSE(tether.addVehicleSample(0.1, Position(kLength, 0.0, 0.0)).ok);
  TetherParams pbd = tether.params();
  pbd.solver = SolverType::kPbd;
  EXPECT_FALSE(tether.setParams(pbd).ok);
  EXPECT_EQ(tether.params().solver, SolverType::kDirect);
  tether.detachVehicle();
  EXPECT_FALSE(tether.vehicleDynamic());
  EXPECT_EQ(tether.vehicleBody(), nullptr);
  // A start three times as far as the locked winch's cable reaches (a helper's vehicle_start of 30 m): taken, the
  // cable laid stretched to it, and said (it was silent: 250 kN at the first step, only an over-tension warning).
  Tether far(lockedTether(1e5), Position::Zero(), Position(kLength, 0.0, 0.0));
  const Status beyond = far.attachVehicleBody(bodyAt(blueRov(), 3.0 * kLength, 0.0), Eigen::Vector3d::Zero());
  ASSERT_TRUE(beyond.ok);
  EXPECT_NE(beyond.message.find("beyond the 10 m of cable the locked winch has out"), std::string::npos)
      << beyond.message;
  EXPECT_NE(beyond.message.find("(strain 2)"), std::string::npos) << beyond.message;
  // A body 2e6 m out (finite, so its own state takes it) puts the attachment beyond the +-1e6 m every position
  // of the tether is held within (Tether::withinLimits): refused, and the end stays kinematic.
  Tether outside(lockedTether(1e5), Position::Zero(), Position(kLength, 0.0, 0.0));
  const Status too_far = outside.attachVehicleBody(bodyAt(blueRov(), 2e6, 0.0), Eigen::Vector3d::Zero());
  EXPECT_FALSE(too_far.ok);
  EXPECT_NE(too_far.message.find("beyond +-1e6 m"), std::string::npos) << too_far.message;
  EXPECT_FALSE(outside.vehicleDynamic());
}

// What the header promises around the steps: attaching to a tether with a free end lays the cable out to the
// attachment point (grown to reach it unless locked); a time step beyond the body's stable limit is refused,
// at attach and as a live change; skipTo keeps the body as it is; reset() returns to a kinematic end.
TEST(VehicleCoupling, AttachSkipResetAndLiveChangesKeepTheirPromises)
{
  TetherParams params = lockedTether(1e5);
  params.winch_mode = WinchMode::kBrake;
  params.cable_length = 20.0;
  params.initial_deployed_length = 2.0;
  Tether tether(params, Position::Zero());
  ASSERT_FALSE(tether.vehicleAttached());
  ASSERT_TRUE(tether.attachVehicleBody(bodyAt(blueRov(), 5.0, 0.2), Eigen::Vector3d(-0.2, 0.0, 0.0)).ok);
  EXPECT_TRUE(tether.vehicleAttached());
  EXPECT_NEAR(tether.deployedLength(), 5.0, 1e-9) << "grown to reach the vehicle";
  EXPECT_NEAR((tether.particle(tether.deployedParticleCount() - 1) - Position(5.0, 0.0, 0.0)).norm(), 0.0, 1e-12);

  // A body whose restoring moment limits its step below the tether's (VehicleBody::stableStepLimit).
  VehicleParams stiff = blueRov();
  stiff.center_of_buoyancy = Eigen::Vector3d(0.0, 0.0, 50.0);
  stiff.inertia = Eigen::Vector3d(1e-3, 1e-3, 1e-3);
  stiff.added_mass.tail<3>().setZero();
  const VehicleBody stiff_body = bodyAt(stiff, 5.0, 0.2);
  ASSERT_LT(stiff_body.stableStepLimit(), params.time_step);
  Tether other(lockedTether(1e5), Position::Zero(), Position(kLength, 0.0, 0.0));
  const Status refused = other.attachVehicleBody(stiff_body, Eigen::Vector3d::Zero());
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.message.find("stable"), std::string::npos) << refused.message;
  TetherParams fine = lockedTether(1e5);
  fine.time_step = 0.5 * stiff_body.stableStepLimit();
  Tether fine_tether(fine, Position::Zero(), Position(kLength, 0.0, 0.0));
  ASSERT_TRUE(fine_tether.attachVehicleBody(stiff_body, Eigen::Vector3d::Zero()).ok);
  const Status live = fine_tether.setParams(lockedTether(1e5));  // back to the 5 ms step: beyond the limit
  EXPECT_FALSE(live.ok);
  EXPECT_NE(live.message.find("stable"), std::string::npos) << live.message;
  EXPECT_EQ(fine_tether.params().time_step, fine.time_step);

  // With a water surface, the limit of the hull crossing it (VehicleBody::stableStepLimitAt): a hull 2 mm high is
  // a stiff heave spring (B / 2 mm), whose limit is below the 50 ms step that the body's restoring moment takes.
  VehicleParams flat = blueRov();
  flat.size.z() = 0.002;
  const VehicleBody flat_body = bodyAt(flat, 5.0, 0.2);
  TetherParams coarse = lockedTether(1e5);
  coarse.time_step = 0.05;
  ASSERT_GT(flat_body.stableStepLimit(), coarse.time_step);
  ASSERT_LT(flat_body.stableStepLimitAt(0.0), coarse.time_step);
  Tether deep(coarse, Position::Zero(), Position(kLength, 0.0, 0.0));
  EXPECT_TRUE(deep.attachVehicleBody(flat_body, Eigen::Vector3d::Zero()).ok) << "no surface";
  coarse.water_surface_z = 10.0;
  Tether surfaced(coarse, Position::Zero(), Position(kLength, 0.0, 0.0));
  const Status crossing = surfaced.attachVehicleBody(flat_body, Eigen::Vector3d::Zero());
  EXPECT_FALSE(crossing.ok);
  EXPECT_NE(crossing.message.find("water surface"), std::string::npos) << crossing.message;

  ASSERT_TRUE(tether.setVehicleThrust(surge(kThrust)).ok);
  for (int i = 0; i < 100; ++i)
  {
    tether.step();
  }
  const Position position = tether.vehicleBody()->position();
  const Twist velocity = tether.vehicleBody()->velocity();
  EXPECT_GT(velocity[0], 0.1) << "it thrusts away";
  ASSERT_TRUE(tether.skipTo(tether.time() + 1.0).ok);
  EXPECT_EQ(tether.vehicleBody()->position(), position) << "not stepped while time is skipped";
  EXPECT_EQ(tether.vehicleBody()->velocity(), velocity);
  const VehicleBody& skipped = *tether.vehicleBody();
  EXPECT_NEAR((tether.particle(tether.deployedParticleCount() - 1) -
               (skipped.position() + skipped.attitude() * Eigen::Vector3d(-0.2, 0.0, 0.0)))
                  .norm(),
              0.0, 1e-12)
      << "the end stays at the attachment point";

  ASSERT_TRUE(tether.reset(0.0).ok);
  EXPECT_FALSE(tether.vehicleDynamic());
  EXPECT_FALSE(tether.vehicleAttached());
  EXPECT_TRUE(tether.addVehicleSample(0.0, Position(3.0, 0.0, 0.0)).ok) << "samples drive the end again";
}

// The hull's wet share (VehicleBody::submergedShare) is what the controller's anti-windup reads before the step
// it asks thrust for, so the body must know the cable's water surface from its attachment and from a live
// change, not only from the next step (which sets it again). The BlueROV2's hull (size.z high, centred on its
// centre of buoyancy) with the surface at that centre: half in, share 0.5 by the definition; with the surface a
// hull's height below: wholly out, 0; with no surface: 1. Seen failing with the surface set only in the step
// (the share read 1 until then).
TEST(VehicleCoupling, TheBodyKnowsTheWaterSurfaceFromItsAttachment)
{
  const VehicleBody body = bodyAt(blueRov(), kLength, 0.2);
  const double middle = body.position().z() + body.params().center_of_buoyancy.z();
  TetherParams params = lockedTether(1e5);
  params.water_surface_z = middle;
  Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
  ASSERT_EQ(body.submergedShare(), 1.0) << "the body given has no surface of its own";
  ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d::Zero()).ok);
  EXPECT_DOUBLE_EQ(tether.vehicleBody()->submergedShare(), 0.5) << "half in, before any step";
  params.water_surface_z = middle - body.params().size.z();
  ASSERT_TRUE(tether.setParams(params).ok);
  EXPECT_DOUBLE_EQ(tether.vehicleBody()->submergedShare(), 0.0) << "wholly out after the live change";
  params.water_surface_z = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(tether.setParams(params).ok);
  EXPECT_DOUBLE_EQ(tether.vehicleBody()->submergedShare(), 1.0) << "no surface: all of it in the water";
}

// Snag: in a World with a pillar (a vertical cylinder, radius 0.3 m, friction 0.3) between the spool and the
// vehicle's way, the BlueROV2 on a locked 10 m tether thrusts 40 N sideways (+y) and pulls its tether round the
// pillar. A dynamic vehicle can pull no harder than its thrust and its momentum can: at every step the pull
// stays below the elastic-impact bound F + u_max sqrt(k m'), u_max the fastest it has gone, m' its heaviest
// translational mass (heave, with added mass), k = EA / s with s the distance from the attachment to the pillar's
// surface, no longer than the free span (so k is an upper bound). At the end (30 s), nearly at rest: the pull
// is the thrust (2%: the drag of its last slow motion), and the spool side is within the capstan band of the
// contact, T_vehicle e^{-mu theta} <= T_spool <= T_vehicle e^{mu theta} (World::topology's CapstanRatio), 1% for
// the tether's drag; over the last 2 s the pull's peak-to-peak stays under 1% of F (no ringing, as in TautStop).
// At EA 1e5 and 1e9 N. Seen failing with the pull left out of the body's step (the pull passes the bound as
// the vehicle stretches its tether); the staggered coupling passes it (the catch is gradual, and the contact's
// sub-steps are short): TautStop is what tells them apart. (Issue 25: a pose-driven vehicle whose path keeps
// going pulls kilonewtons round a pillar, scenarios/pillar_wrap.yaml.)
TEST(VehicleCoupling, ASnaggedVehiclePullsNoHarderThanItsThrustAndMomentumCan)
{
  for (const double axial_stiffness : {1e5, 1e9})
  {
    SCOPED_TRACE(axial_stiffness);
    const TetherParams params = lockedTether(axial_stiffness);
    const VehicleParams vehicle = blueRov();
    auto owned = std::make_unique<Tether>(params, Position::Zero(), Position(9.0, 0.0, 0.0));
    VehicleBody body;
    ASSERT_TRUE(body.setParams(vehicle).ok);
    const Eigen::Quaterniond facing_y(Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Eigen::Vector3d::UnitZ()));
    ASSERT_TRUE(body.setState({9.0, 0.0, 0.0}, facing_y, Twist::Zero()).ok);
    ASSERT_TRUE(owned->attachVehicleBody(body, Eigen::Vector3d::Zero()).ok);
    ASSERT_TRUE(owned->setVehicleThrust(surge(kThrust)).ok);
    Tether& tether = *owned;
    World world;
    ASSERT_TRUE(world.add("rov", std::move(owned)).ok);
    ObstacleSpec pillar;
    pillar.name = "pillar";
    pillar.type = ShapeType::Cylinder;
    pillar.position = Position(5.0, 0.5, 0.0);
    pillar.radius = 0.3;
    pillar.length = 4.0;
    pillar.friction = 0.3;
    Status made;
    std::vector<std::unique_ptr<Obstacle>> obstacles;
    obstacles.push_back(makePrimitive(pillar, &made));
    ASSERT_TRUE(made.ok) << made.message;
    ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);

    const double heaviest = vehicle.mass + vehicle.added_mass.head<3>().maxCoeff();
    double fastest = 0.0;
    double lowest_late = 1e300, highest_late = 0.0;  // the pull over the last 2 s
    for (int i = 1; i <= 3000; ++i)
    {
      ASSERT_TRUE(world.advanceTo(0.01 * i).ok);
      ASSERT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
      const VehicleBody& now = *tether.vehicleBody();
      fastest = std::max(fastest, now.velocity().head<3>().norm());
      Position off_axis = now.position() - pillar.position;
      off_axis.z() = 0.0;
      const double span = off_axis.norm() - pillar.radius;
      const double bound = kThrust + fastest * std::sqrt(axial_stiffness / span * heaviest);
      const double pull = tether.vehicleForce().norm();
      ASSERT_LE(pull, bound) << "t " << tether.time();
      if (i > 2800)
      {
        lowest_late = std::min(lowest_late, pull), highest_late = std::max(highest_late, pull);
      }
    }
    std::vector<TopologyEntry> topology;
    world.topology(topology);
    double capstan = 0.0;
    for (const TopologyEntry& entry : topology)
    {
      capstan = entry.kind == TopologyEntry::Kind::CapstanRatio && !entry.object_is_tether ? entry.value : capstan;
    }
    ASSERT_GT(capstan, 1.05) << "the tether does not wrap the pillar: the test tests nothing";
    const double at_vehicle = tether.vehicleForce().norm();
    EXPECT_NEAR(at_vehicle, kThrust, 0.02 * kThrust);
    EXPECT_LT(highest_late - lowest_late, 0.01 * kThrust) << "the pull rings";
    const double at_spool = tether.summary().tension_spool;
    EXPECT_GE(at_spool, at_vehicle / capstan * 0.99);
    EXPECT_LE(at_spool, at_vehicle * capstan * 1.01);
  }
}

// The attachment point's inverse mass with and without predict() for the step: the same factorisation of the
// body's step (M + h D, the water's damping on the share of the hull in it), so the same number to the bit,
// wet or half out of the water; and half out, the hull is damped less, so the point is more mobile than wet.
// Seen failing with the fallback's damping taken on the whole hull (it mirrored the body's step by hand).
TEST(VehicleCoupling, TheEndsInverseMassIsThePredictionsWithOrWithoutOne)
{
  VehicleBody body = bodyAt(blueRov(), 0.0, 0.0);
  Twist moving;
  moving << 0.4, 0.1, -0.2, 0.05, -0.1, 0.2;
  ASSERT_TRUE(body.setState(body.position(), body.attitude(), moving).ok);
  const Position neighbour(-1.0, 0.3, 0.2);
  const Position end(0.1, -0.2, 0.1);
  const double h = 0.005;
  double cold_at[2] = {0.0, 0.0};
  for (const bool half : {false, true})
  {
    SCOPED_TRACE(half ? "half out of the water" : "under water");
    VehicleCoupling coupling(body, Eigen::Vector3d(-0.2, 0.0, 0.1));
    // The surface at the hull's mid-height puts half of it out (VehicleBody::submergedShare).
    coupling.setWaterSurface(half ? body.position().z() : 10.0);
    const double cold = coupling.inverseMass(neighbour, end, h);
    Position predicted;
    ASSERT_TRUE(coupling.predict(h, &predicted).ok);
    EXPECT_EQ(coupling.inverseMass(neighbour, end, h), cold);
    EXPECT_GT(cold, 0.0);
    cold_at[half ? 1 : 0] = cold;
  }
  EXPECT_GT(cold_at[1], cold_at[0]) << "less of the hull in the water: less damped, more mobile";
}

// A solve that diverges is no force on the vehicle. The 5 t vehicle (moving at 0.5 m/s in surge, thrust off) on
// a locked, nearly inextensible 10 m tether (EA 1e9 N, weightless), 2 sub-steps a step and 1 Newton iteration
// (2 more to rescue a diverged one), its spool moved 10 m away at every step: the first step drags the vehicle
// after it, and the second's first sub-step diverges (a segment at strain 1 or more after the rescue), so the
// tether is re-laid at rest. Physics: the folded chain's particle moves are no pull, so over that step the body
// moves as a free body does (here with nothing on it but its own damping and nothing from the weightless cable)
// for the whole step, both sub-steps: a copy of the body stepped twice by the sub-step with no wrench, to
// rounding (1e-9 m, 1e-9 m/s). Seen failing with the diverged solve's pull applied (0.25 m and 323 m/s off, and
// 1.2e9 N reported as the pull) and with the step's second sub-step skipped for the body (0.40 m, 62 m/s). Should the
// failure move to another sub-step (a solver change), the counts asserted first say so.
TEST(VehicleCoupling, ADivergedSolvePullsNothingAndTheBodyTakesTheWholeStep)
{
  TetherParams params = lockedTether(1e9);
  params.substeps = 2;
  params.iterations = 1;
  Tether tether(params, Position::Zero(), Position(kLength, 0.0, 0.0));
  VehicleBody body = bodyAt(workClass(), kLength, 0.0);
  ASSERT_TRUE(body.setState(body.position(), body.attitude(), surge(0.5)).ok);
  ASSERT_TRUE(tether.attachVehicleBody(body, Eigen::Vector3d::Zero()).ok);
  for (int step = 1; step <= 2; ++step)
  {
    body = *tether.vehicleBody();
    ASSERT_TRUE(tether.setSpoolPosition(Position(-10.0 * step, 0.0, 0.0)).ok);
    tether.step();
    ASSERT_EQ(tether.recoveryCount(), step == 2 ? 1u : 0u) << "this test needs the second step to blow up";
  }
  ASSERT_NE(tether.lastFailure().find("diverged"), std::string::npos) << tether.lastFailure();
  ASSERT_EQ(tether.solverEffort().substeps, 3u) << "the blow-up must be the second step's first sub-step";
  VehicleBody free = body;
  const double h = params.time_step / params.substeps;
  for (int k = 0; k < params.substeps; ++k)
  {
    ASSERT_TRUE(free.step(h, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
  }
  const VehicleBody& coupled = *tether.vehicleBody();
  EXPECT_NEAR((coupled.position() - free.position()).norm(), 0.0, 1e-9);
  EXPECT_NEAR((coupled.velocity() - free.velocity()).norm(), 0.0, 1e-9);
  EXPECT_NEAR(tether.vehicleForce().norm(), 0.0, 1e-9) << "a weightless cable re-laid at rest pulls nothing";
  const Position end = tether.particle(tether.deployedParticleCount() - 1);
  EXPECT_NEAR((end - coupled.position()).norm(), 0.0, 1e-12) << "re-laid to where the body is";
}

}  // namespace
}  // namespace rov_tether::test
