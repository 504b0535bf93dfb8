// The tether's linearisation at a kinematic vehicle end (Tether::vehicleEndLinearisation, end_linearisation.hpp):
// K against finite differences of the real step, the closed-form limits of a straight chain, its symmetry and
// sign, the refusals, and that asking for it changes nothing.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/vehicle_body.hpp"
#include "test_helpers.hpp"

namespace rov_tether
{
namespace
{

using test::succeeded;

/// A locked 2 m tether in 20 segments of 0.1 m from the spool at the origin to a kinematic vehicle at `vehicle`.
TetherParams lockedParams(double bending_stiffness)
{
  TetherParams params;
  params.solver = SolverType::kDirect;
  params.winch_mode = WinchMode::kLocked;
  params.cable_length = params.initial_deployed_length = 2.0;
  params.segment_length = 0.1;
  params.bending_stiffness = bending_stiffness;
  return params;
}

/// The last sub-step's length h and the masses / h^2 of the free particles and the segments' forces [N].
struct ChainNumbers
{
  std::vector<double> mass_per_step;  ///< m_i / h^2 of free particle i (0 for pinned ones) [N/m].
  std::vector<double> tension;        ///< lambda_k / h^2 [N].
  std::vector<double> length;         ///< |d_k| [m].
  std::vector<double> rest;           ///< L_k [m].
};

ChainNumbers chainNumbers(const Tether& sim)
{
  const Cable& cable = sim.state();
  const double h = sim.params().time_step / sim.params().substeps;
  ChainNumbers numbers;
  for (std::size_t i = cable.first; i < cable.size(); ++i)
  {
    numbers.mass_per_step.push_back(cable.inv_mass[i] > 0.0 ? 1.0 / (cable.inv_mass[i] * h * h) : 0.0);
  }
  for (std::size_t k = cable.first; k + 1 < cable.size(); ++k)
  {
    numbers.tension.push_back(sim.multipliers().stretch[k] / (h * h));
    numbers.length.push_back((cable.position(k + 1) - cable.position(k)).norm());
    numbers.rest.push_back(cable.rest[k]);
  }
  return numbers;
}

/// Bounds on the stiffness S a chain of springs s_k (spool pinned, end moved) with masses mu_i / h^2 at its
/// free particles offers its end in one step (the Schur complement of the step's Hessian onto the end, in one
/// direction of a straight chain, where the directions decouple). S is the least of z^T H z over the free
/// particles' moves z with the end's move 1 (the Hessian is positive definite). Without the masses the least
/// is the springs in series, s_series; the masses only add, so S >= s_series. The springs' own static shape
/// u_i (the fraction of 1 / s_series up to particle i) is one such z: S <= s_series + sum mu_i u_i^2.
struct SeriesBounds
{
  double lower;
  double upper;
};

SeriesBounds seriesBounds(const std::vector<double>& springs, const std::vector<double>& mass_per_step)
{
  double compliance = 0.0;
  for (const double s : springs)
  {
    compliance += 1.0 / s;
  }
  double inertia = 0.0;
  double reached = 0.0;
  for (std::size_t i = 1; i + 1 < mass_per_step.size(); ++i)
  {
    reached += 1.0 / springs[i - 1];
    const double u = reached / compliance;
    inertia += mass_per_step[i] * u * u;
  }
  return {1.0 / compliance, 1.0 / compliance + inertia};
}

/// The largest tension ratio h^2 T (w_a + w_b) / |d| of the last step: above 1/4 `direct` takes the primal path
/// (Newton with the full Hessian, direct_solver.hpp), whose solution meets the step's equations exactly.
double largestTensionRatio(const Tether& sim)
{
  const Cable& cable = sim.state();
  double largest = 0.0;
  for (std::size_t k = cable.first; k + 1 < cable.size(); ++k)
  {
    const double length = (cable.position(k + 1) - cable.position(k)).norm();
    largest = std::max(largest, sim.multipliers().stretch[k] * (cable.inv_mass[k] + cable.inv_mass[k + 1]) / length);
  }
  return largest;
}

/// The pull on the vehicle after one more step with the end at `end` (a sample at the step's end time).
Force pullAfterStepTo(Tether& sim, const Position& end)
{
  EXPECT_TRUE(succeeded(sim.addVehicleSample(sim.nextStepTime(), end)));
  sim.step();
  return sim.vehicleForce();
}

/// K by central differences of the real step: seven identical tethers (made by `make`, run the same steps:
/// a run repeats bit for bit) take one more step with the end at x0 and at x0 +- delta e_a. Returns the base
/// tether's linearisation in `linearised`.
Eigen::Matrix3d finiteDifferenceStiffness(const std::function<std::unique_ptr<Tether>()>& make, const Position& x0,
                                          double delta, EndLinearisation* linearised)
{
  std::unique_ptr<Tether> base = make();
  pullAfterStepTo(*base, x0);
  EXPECT_TRUE(succeeded(base->vehicleEndLinearisation(linearised)));
  Eigen::Matrix3d stiffness;
  for (int axis = 0; axis < 3; ++axis)
  {
    const Position move = delta * Position::Unit(axis);
    std::unique_ptr<Tether> plus = make();
    std::unique_ptr<Tether> minus = make();
    stiffness.col(axis) = (pullAfterStepTo(*plus, x0 + move) - pullAfterStepTo(*minus, x0 - move)) / (2.0 * delta);
  }
  return stiffness;
}

/// A 2 m tether hanging under its weight (20 N/m in water) to a vehicle at x0 off every axis, settled for 3 s
/// with the default water damping and noise (or Morison drag in a 0.2 m/s current across, whose added mass
/// makes each particle's mass anisotropic), tolerance 1e-12.
std::unique_ptr<Tether> hangingTether(double bending_stiffness, const Position& x0, bool morison = false)
{
  TetherParams params = lockedParams(bending_stiffness);
  params.weight_in_water = 20.0;
  params.solver_tolerance = 1e-12;
  if (morison)
  {
    params.drag_model = DragModel::kMorison;
    params.current = {0.0, 0.2, 0.0};
  }
  auto sim = std::make_unique<Tether>(params, Position::Zero(), x0);
  EXPECT_TRUE(succeeded(sim->advance(3.0)));
  return sim;
}

// (1) K against finite differences of the step, with and without bending, and with Morison drag (added mass
// across the cable). The chain is pulled hard enough (20 N/m) for `direct`'s primal path, whose solution meets
// the step's equations; on the dual path the force balance is met only as the fast projection meets it (see
// docs/model.md), and the real step differs from its linearisation by more than this budget. Error budget of
// the central difference (F'' ~ K / l across a segment of l = 0.1 m, so its truncation (delta / l)^2 / 6 ~ 1e-10
// of |K|): each solve stops with |C - alpha lambda| <= tolerance x l, a pull within EA x tolerance = 1e-7 N;
// the difference of two such pulls over 2 delta is within EA x tolerance / delta = 0.1 N/m at delta = 1 um.
// Bound: 0.1 N/m + 1e-6 |K|.
TEST(EndLinearisation, StiffnessIsTheFiniteDifferenceOfTheStep)
{
  const Position x0(1.2, 0.4, -0.9);
  const double delta = 1e-6;
  struct Case
  {
    const char* name;
    double bending_stiffness;
    bool morison;
  };
  for (const Case& c : {Case{"EI 0", 0.0, false}, Case{"EI 0.2", 0.2, false}, Case{"EI 0, Morison", 0.0, true}})
  {
    SCOPED_TRACE(c.name);
    EXPECT_GT(largestTensionRatio(*hangingTether(c.bending_stiffness, x0, c.morison)), 0.25);  // the primal path
    EndLinearisation linearised;
    const Eigen::Matrix3d difference = finiteDifferenceStiffness(
        [&] { return hangingTether(c.bending_stiffness, x0, c.morison); }, x0, delta, &linearised);
    ASSERT_TRUE(linearised.taut);
    const double bound = 1e5 * 1e-12 / delta + 1e-6 * linearised.stiffness.cwiseAbs().maxCoeff();
    EXPECT_LE((linearised.stiffness - difference).cwiseAbs().maxCoeff(), bound)
        << "K\n"
        << linearised.stiffness << "\nfinite differences\n"
        << difference;
    // It is not trivially small: along the chord the chain is far stiffer than the bound.
    EXPECT_GT(linearised.stiffness.cwiseAbs().maxCoeff(), 1e3 * bound);
    EXPECT_EQ(linearised.damping, Eigen::Matrix3d::Zero());  // C = 0: the step has no term in the end's velocity
  }
}

// (1) A slack end: the vehicle pushed 5 cm towards the spool in one step leaves the last segment of a
// weightless cable (EI 0: it cannot push) shorter than its rest length. Nothing pulls, K = 0 and taut is
// false, and moving the end by +-1 um (far less than the slack) keeps the pull exactly zero.
TEST(EndLinearisation, ASlackEndHasNoStiffness)
{
  const Position laid(1.5, 0.0, 0.0);
  const Position x0 = laid - Position(0.05, 0.0, 0.0);
  auto make = [&]
  {
    TetherParams params = lockedParams(0.0);
    params.noise = 0.0;
    auto sim = std::make_unique<Tether>(params, Position::Zero(), laid);
    EXPECT_TRUE(succeeded(sim->advance(0.5)));
    return sim;
  };
  EndLinearisation linearised;
  const Eigen::Matrix3d difference = finiteDifferenceStiffness(make, x0, 1e-6, &linearised);
  EXPECT_FALSE(linearised.taut);
  EXPECT_EQ(linearised.force, Force::Zero());
  EXPECT_EQ(linearised.stiffness, Eigen::Matrix3d::Zero());
  EXPECT_EQ(linearised.damping, Eigen::Matrix3d::Zero());
  EXPECT_EQ(difference, Eigen::Matrix3d::Zero());
}

/// A straight 2 m chain along x stretched to `stretched` [m] (no weight, drag or noise: it stays on the axis),
/// with EA and mass per length given, after `steps` steps.
std::unique_ptr<Tether> straightChain(double axial_stiffness, double mass_per_length, double stretched, int steps)
{
  TetherParams params = lockedParams(0.0);
  params.axial_stiffness = axial_stiffness;
  params.mass_per_length = mass_per_length;
  params.drag = 1.0;
  params.noise = 0.0;
  params.solver_tolerance = 1e-12;
  auto sim = std::make_unique<Tether>(params, Position::Zero(), Position(stretched, 0.0, 0.0));
  for (int k = 0; k < steps; ++k)
  {
    sim->step();
  }
  return sim;
}

// (2) A light chain: the particles' masses per step, 1e-4 kg / h^2 = 4 N/m, are tiny against the segments'
// EA / l = 1e8 N/m and T / l = 1e6 N/m (EA 1e7 N stretched by 1%). Within a step the chain answers as its springs in
// series: along it EA / L_total, across it T / L_total (a string under T turned about the spool). seriesBounds gives
// the exact band the masses leave: [series, series + sum mu_i u_i^2], under 1e-3 of the series stiffness here
// (checked).
TEST(EndLinearisation, ALightChainAnswersWithItsWholeLength)
{
  const double ea = 1e7;
  const std::unique_ptr<Tether> sim = straightChain(ea, 0.001, 2.02, 20);
  EndLinearisation linearised;
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&linearised)));
  ASSERT_TRUE(linearised.taut);
  const ChainNumbers chain = chainNumbers(*sim);
  std::vector<double> axial;
  std::vector<double> across;
  for (std::size_t k = 0; k < chain.tension.size(); ++k)
  {
    axial.push_back(ea / chain.rest[k]);
    across.push_back(chain.tension[k] / chain.length[k]);
  }
  const SeriesBounds along_bounds = seriesBounds(axial, chain.mass_per_step);
  const SeriesBounds across_bounds = seriesBounds(across, chain.mass_per_step);
  EXPECT_LT(along_bounds.upper / along_bounds.lower - 1.0, 1e-3);
  EXPECT_LT(across_bounds.upper / across_bounds.lower - 1.0, 1e-3);
  const Eigen::Matrix3d& k = linearised.stiffness;
  const double rounding = 1e-9 * k.cwiseAbs().maxCoeff();
  EXPECT_GE(-k(0, 0), along_bounds.lower - rounding);
  EXPECT_LE(-k(0, 0), along_bounds.upper + rounding);
  for (int axis : {1, 2})
  {
    EXPECT_GE(-k(axis, axis), across_bounds.lower - rounding) << axis;
    EXPECT_LE(-k(axis, axis), across_bounds.upper + rounding) << axis;
  }
  EXPECT_LE(std::abs(k(0, 1)) + std::abs(k(0, 2)) + std::abs(k(1, 2)), rounding);  // directions decouple
  // The closed forms themselves: EA / L_total exactly is the axial series (the rest lengths add to 2 m); the
  // tension is uniform (checked within 1e-3), so the transverse series is T / L_total within 1e-3 + 1e-3.
  const double tension = chain.tension.back();
  for (const double t : chain.tension)
  {
    EXPECT_NEAR(t, tension, 1e-3 * tension);
  }
  EXPECT_NEAR(-k(0, 0), ea / 2.0, 1e-3 * ea / 2.0);
  EXPECT_NEAR(-k(1, 1), tension / 2.02, 2e-3 * tension / 2.02);
}

// (2) A heavy chain: the last free particle's mass per step, 100 kg / h^2 = 4e6 N/m, is large against the
// last segment's EA / l = 1e4 N/m and T / |d|: the chain cannot move within a step, and the end feels the last
// segment alone, EA / l_last and T / |d_last|. Bound: the Hessian holds at least that segment and that
// particle's mass, so the Schur complement s lies in [s mu / (s + mu), s] in each direction (the least of
// s (1 - y)^2 + mu y^2 over the particle's move y), within 0.25% of s here.
TEST(EndLinearisation, AHeavyChainAnswersWithItsLastSegment)
{
  const double ea = 1e3;
  const std::unique_ptr<Tether> sim = straightChain(ea, 1000.0, 2.02, 2);
  EndLinearisation linearised;
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&linearised)));
  ASSERT_TRUE(linearised.taut);
  const ChainNumbers chain = chainNumbers(*sim);
  const double mu = chain.mass_per_step[chain.mass_per_step.size() - 2];
  const double along = ea / chain.rest.back();
  const double across = chain.tension.back() / chain.length.back();
  ASSERT_GT(across, 50.0);  // the last segment is pulled (laid out stretched by 1%: T = 10 N, T / |d| = 99 N/m)
  const Eigen::Matrix3d& k = linearised.stiffness;
  const double rounding = 1e-9 * k.cwiseAbs().maxCoeff();
  EXPECT_GE(-k(0, 0), along * mu / (along + mu) - rounding);
  EXPECT_LE(-k(0, 0), along + rounding);
  for (int axis : {1, 2})
  {
    EXPECT_GE(-k(axis, axis), across * mu / (across + mu) - rounding) << axis;
    EXPECT_LE(-k(axis, axis), across + rounding) << axis;
  }
  // And not the light chain's: the whole length's EA / L_total is 20 times softer.
  EXPECT_GT(-k(0, 0), 10.0 * ea / 2.0);
}

// (2b) The horizon: the same heavy chain linearised over a step of 1000 s instead of h (what a simulator whose
// state runs that far ahead of x0 feels). The particles' inertia per step becomes m / tau^2 = (h / tau)^2 of
// what it was (4e6 N/m -> 4e-6 N/m), so the chain answers as a light one: the series bounds of test (2), with
// the masses scaled, hold; they are within 1e-3 of EA / L_total and T / L_total. A horizon shorter than h is
// the step's own K, bit for bit; a negative or NaN one is refused.
TEST(EndLinearisation, ALongHorizonAnswersWithTheWholeChain)
{
  const double ea = 1e3;
  const std::unique_ptr<Tether> sim = straightChain(ea, 1000.0, 2.02, 2);
  const double h = sim->params().time_step / sim->params().substeps;
  const double tau = 1000.0;
  EndLinearisation step;
  EndLinearisation shorter;
  EndLinearisation linearised;
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&step)));
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&shorter, 0.5 * h)));
  EXPECT_EQ(shorter.stiffness, step.stiffness);
  EXPECT_EQ(step.horizon, h);
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&linearised, tau)));
  ASSERT_TRUE(linearised.taut);
  EXPECT_EQ(linearised.horizon, tau);
  EXPECT_EQ(linearised.force, step.force);
  const ChainNumbers chain = chainNumbers(*sim);
  std::vector<double> mass_per_horizon;
  for (const double mu : chain.mass_per_step)
  {
    mass_per_horizon.push_back(mu * (h / tau) * (h / tau));
  }
  std::vector<double> axial;
  std::vector<double> across;
  for (std::size_t k = 0; k < chain.tension.size(); ++k)
  {
    axial.push_back(ea / chain.rest[k]);
    across.push_back(chain.tension[k] / chain.length[k]);
  }
  const SeriesBounds along_bounds = seriesBounds(axial, mass_per_horizon);
  const SeriesBounds across_bounds = seriesBounds(across, mass_per_horizon);
  const Eigen::Matrix3d& k = linearised.stiffness;
  const double rounding = 1e-9 * k.cwiseAbs().maxCoeff();
  EXPECT_GE(-k(0, 0), along_bounds.lower - rounding);
  EXPECT_LE(-k(0, 0), along_bounds.upper + rounding);
  EXPECT_NEAR(-k(0, 0), ea / 2.0, 1e-3 * ea / 2.0);
  for (int axis : {1, 2})
  {
    EXPECT_GE(-k(axis, axis), across_bounds.lower - rounding) << axis;
    EXPECT_LE(-k(axis, axis), across_bounds.upper + rounding) << axis;
  }
  EndLinearisation refused;
  EXPECT_FALSE(sim->vehicleEndLinearisation(&refused, -1.0).ok);
  EXPECT_FALSE(sim->vehicleEndLinearisation(&refused, std::nan("")).ok);
}

// (3) A cable's K is minus the Schur complement of a symmetric Hessian: symmetric (to rounding, 1e-9 of its
// largest entry), and while every segment pulls, negative semi-definite (moving the end away pulls it back
// harder: -K >= 0) and no stiffer than the last segment held alone, B / h^2 = EA / L n n^T + T / |d| (I - n n^T)
// (-K = (B - B G B) / h^2 with G = H_ff^-1's block >= 0).
TEST(EndLinearisation, ACableStiffnessIsSymmetricAndRestoring)
{
  const Position x0(1.2, 0.4, -0.9);
  const std::unique_ptr<Tether> sim = hangingTether(0.0, x0);
  EndLinearisation linearised;
  ASSERT_TRUE(succeeded(sim->vehicleEndLinearisation(&linearised)));
  ASSERT_TRUE(linearised.taut);
  const Eigen::Matrix3d& k = linearised.stiffness;
  const double rounding = 1e-9 * k.cwiseAbs().maxCoeff();
  EXPECT_LE((k - k.transpose()).cwiseAbs().maxCoeff(), rounding) << k;
  const Eigen::Matrix3d restoring = -0.5 * (k + k.transpose());
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(restoring).eigenvalues().minCoeff(), -rounding);
  const ChainNumbers chain = chainNumbers(*sim);
  const std::size_t n = sim->deployedParticleCount();
  const Position along = (sim->particle(n - 1) - sim->particle(n - 2)).normalized();
  const double tension = chain.tension.back();
  const Eigen::Matrix3d last =
      sim->params().axial_stiffness / chain.rest.back() * along * along.transpose() +
      tension / chain.length.back() * (Eigen::Matrix3d::Identity() - along * along.transpose());
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(last - restoring).eigenvalues().minCoeff(), -rounding);
  // F0 is the pull the tether reports, at the end's place and time.
  EXPECT_EQ(linearised.force, sim->vehicleForce());
  EXPECT_EQ(linearised.position, sim->particle(n - 1));
  EXPECT_EQ(linearised.time, sim->time());
  // ...the last segment's pull back along it plus the weight in water of the half segment the end carries.
  const Force half_segment(0.0, 0.0, -0.5 * sim->params().weight_in_water * chain.rest.back());
  EXPECT_NEAR((linearised.force - half_segment + tension * along).norm(), 0.0, 1e-9 * tension);
}

// v0 is the end's motion over the last step: a vehicle sampled moving at 0.2 m/s along y.
TEST(EndLinearisation, VelocityIsTheEndsMotionOverTheLastStep)
{
  TetherParams params = lockedParams(0.0);
  Tether sim(params, Position::Zero(), Position(1.5, 0.0, 0.0));
  ASSERT_TRUE(succeeded(sim.addVehicleSample(0.0, Position(1.5, 0.0, 0.0))));
  ASSERT_TRUE(succeeded(sim.addVehicleSample(1.0, Position(1.5, 0.2, 0.0))));
  ASSERT_TRUE(succeeded(sim.advance(0.5)));
  EndLinearisation linearised;
  ASSERT_TRUE(succeeded(sim.vehicleEndLinearisation(&linearised)));
  EXPECT_NEAR(linearised.velocity.y(), 0.2, 1e-9);
  EXPECT_NEAR(linearised.velocity.x(), 0.0, 1e-12);
  EXPECT_NEAR(linearised.position.y(), 0.2 * sim.time(), 1e-9);
}

// (4) Refused without a vehicle, with a dynamic one, and for a solver without an implicit step.
TEST(EndLinearisation, IsRefusedWhereItHasNoMeaning)
{
  EndLinearisation linearised;
  Tether free_end(lockedParams(0.0), Position::Zero());
  free_end.step();
  const Status no_vehicle = free_end.vehicleEndLinearisation(&linearised);
  EXPECT_FALSE(no_vehicle.ok);
  EXPECT_NE(no_vehicle.message.find("no vehicle"), std::string::npos) << no_vehicle.message;

  Tether dynamic(lockedParams(0.0), Position::Zero(), Position(1.5, 0.0, 0.0));
  VehicleBody body;
  ASSERT_TRUE(body.setState({1.7, 0.0, 0.0}, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  ASSERT_TRUE(succeeded(dynamic.attachVehicleBody(body, Eigen::Vector3d(-0.2, 0.0, 0.0))));
  dynamic.step();
  const Status coupled = dynamic.vehicleEndLinearisation(&linearised);
  EXPECT_FALSE(coupled.ok);
  EXPECT_NE(coupled.message.find("VehicleCoupling"), std::string::npos) << coupled.message;

  for (const SolverType solver : {SolverType::kXpbd, SolverType::kPbd, SolverType::kLumpedMass})
  {
    TetherParams params = lockedParams(0.0);
    params.solver = solver;
    params.substeps = solver == SolverType::kLumpedMass ? 60 : 1;
    Tether other(params, Position::Zero(), Position(1.5, 0.0, 0.0));
    other.step();
    const Status refused = other.vehicleEndLinearisation(&linearised);
    EXPECT_FALSE(refused.ok) << toString(solver);
    EXPECT_NE(refused.message.find("use solver 'direct'"), std::string::npos) << refused.message;
  }
}

// Asking for the linearisation changes nothing: its solves use a workspace of their own, so a tether that asks
// every step runs bit for bit as one that never asks (rod and cable, dual and primal paths).
TEST(EndLinearisation, AskingChangesNothing)
{
  for (const double bending_stiffness : {0.0, 0.2})
  {
    const Position x0(1.2, 0.4, -0.9);
    TetherParams params = lockedParams(bending_stiffness);
    params.weight_in_water = 2.0;
    Tether asking(params, Position::Zero(), x0);
    Tether quiet(params, Position::Zero(), x0);
    EndLinearisation linearised;
    for (int k = 0; k < 200; ++k)
    {
      asking.step();
      quiet.step();
      ASSERT_TRUE(succeeded(asking.vehicleEndLinearisation(&linearised)));
    }
    for (std::size_t k = 0; k < asking.deployedParticleCount(); ++k)
    {
      EXPECT_EQ(asking.particle(k), quiet.particle(k)) << k;
    }
    EXPECT_EQ(asking.vehicleForce(), quiet.vehicleForce());
  }
}

}  // namespace
}  // namespace rov_tether
