// The vehicle's rigid body (VehicleBody, Fossen's 6-DOF form) against closed forms and balances. Each bound
// says where it comes from; the integrator is the four-part split of vehicle_body.hpp (first order in h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rov_tether/core/vehicle_body.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kPi = 3.14159265358979323846;
constexpr double kStep = 0.01;  // [s] the 100 Hz vehicle

/// The BlueROV2 Heavy (defaults) made neutrally buoyant: rho g V = m g, so only the restoring moment of r_B
/// 0.01 m above r_G remains.
VehicleParams neutral()
{
  VehicleParams p;
  p.displaced_volume = p.mass / p.water_density;
  return p;
}

/// A free body: the BlueROV2 Heavy neutrally buoyant with r_B = r_G (no restoring wrench) and no damping.
VehicleParams freeBody()
{
  VehicleParams p = neutral();
  p.center_of_buoyancy.setZero();
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  return p;
}

/// A velocity moving and turning about every axis [m/s, rad/s].
Twist spinning() { return (Twist() << 0.6, -0.4, 0.3, 0.8, -0.5, 1.2).finished(); }

VehicleBody bodyWith(const VehicleParams& params)
{
  VehicleBody body;
  EXPECT_TRUE(body.setParams(params).ok);
  return body;
}

/// A dynamic end's sub-step (VehicleCoupling's path): the trial without `added`, then taken again with it.
void tryThenStep(VehicleBody& body, double h, const Wrench& added)
{
  VehicleStepStart start;
  ASSERT_TRUE(body.startStep(h, &start).ok);
  VehicleStepTrial trial;
  Eigen::Vector3d position;
  Eigen::Quaterniond attitude;
  ASSERT_TRUE(body.stepped(start, Wrench::Zero(), Wrench::Zero(), &position, &attitude, &trial).ok);
  ASSERT_TRUE(body.stepAgain(start, trial, added).ok);
}

void run(VehicleBody* body, double duration, const Wrench& thrust, const Wrench& external = Wrench::Zero())
{
  const int steps = static_cast<int>(std::lround(duration / kStep));
  for (int i = 0; i < steps; ++i)
  {
    ASSERT_TRUE(body->step(kStep, thrust, external, nullptr).ok);
  }
}

Wrench axis(int i, double value)
{
  Wrench w = Wrench::Zero();
  w[i] = value;
  return w;
}

/// Closed form of m' u' = -a u - b u|u| from u0 > 0: u(t) = a / ((a / u0 + b) e^{a t / m'} - b), and for
/// a = 0, u0 / (1 + b u0 t / m').
double decay(double u0, double a, double b, double m, double t)
{
  if (a == 0.0)
  {
    return u0 / (1.0 + b * u0 * t / m);
  }
  return a / ((a / u0 + b) * std::exp(a * t / m) - b);
}

/// Steady speed U > 0 where F = a U + b U^2.
double steadySpeed(double force, double a, double b)
{
  return b == 0.0 ? force / a : (-a + std::sqrt(a * a + 4.0 * b * force)) / (2.0 * b);
}

/// Angle between the body's z axis and the world's [rad].
double tilt(const VehicleBody& body)
{
  return std::acos(std::clamp((body.attitude() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0));
}

// 1. Free surge decay, thrust off: u(t) against the closed form of m' u' = -Xu u - Xuu u|u|, m' = m - X_udot.
// Bound: with nothing but surge moving, one step is u' = m' u / (m' + h (a + b u)) (the kick and the
// Coriolis step do nothing). Its Taylor expansion, u' = u + h u_dot + h^2 k^2 u (k = (a + b u) / m'), against the exact
// u + h u_dot + h^2 u_ddot / 2 leaves a local error h^2 a k u / (2 m') = -h^2 (a / 2 m') u_dot > 0: the scheme
// lags. The step map is a contraction, so the global error is at most the sum of the local ones:
// 0 <= u_h(t) - u(t) <= (h / 2) (a / m') (u0 - u(t)) (3.4e-3 m/s at most here); O(h^3) terms are below it
// at h = 0.01 s (0.93 of the bound at the worst step). Fails with the added mass left out (m' = m) and with
// the damping explicit (error ~h, not h a / m').
TEST(VehicleBody, FreeSurgeDecayFollowsTheClosedForm)
{
  const VehicleParams p = neutral();
  VehicleBody body = bodyWith(p);
  const double u0 = 1.0;
  ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), axis(0, u0)).ok);
  const double m = p.mass + p.added_mass[0];
  const double a = p.linear_damping[0];
  const double b = p.quadratic_damping[0];
  for (int n = 1; n <= 500; ++n)
  {
    ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    const double t = n * kStep;
    const double exact = decay(u0, a, b, m, t);
    const double error = body.velocity()[0] - exact;
    const double bound = 0.5 * kStep * (a / m) * (u0 - exact);
    ASSERT_GE(error, -1e-12) << "t " << t;
    ASSERT_LE(error, bound + 1e-12) << "t " << t << ": u " << body.velocity()[0] << ", closed form " << exact;
  }
  // Nothing else moved: no sway, heave or turn from a pure surge decay.
  EXPECT_LT(body.velocity().tail<5>().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(tilt(body), 1e-12);
}

// 2. Steady thrust F = 40 N (the experiment): the steady surge speed solves F = Xu U + Xuu U^2
// (0.4915 m/s). Bound 0.5% (the issue's); the split is exact at a steady state, since the damping takes |u|
// from the step's start: (m' + h (a + b U)) U = m' U + h F. Time constant m' / (a + 2 b U) = 0.13 s, so
// 10 s is 75 of them. Fails with |u| taken after the kick (U 2% low) or with the damping explicit.
TEST(VehicleBody, SteadyThrustGivesTheDragBalanceSpeed)
{
  const VehicleParams p = neutral();
  VehicleBody body = bodyWith(p);
  const double thrust = 40.0;
  run(&body, 10.0, axis(0, thrust));
  const double expected = steadySpeed(thrust, p.linear_damping[0], p.quadratic_damping[0]);
  EXPECT_NEAR(body.velocity()[0], expected, 0.005 * expected);
  EXPECT_NEAR(body.position().x(), expected * 10.0, 0.05 * expected * 10.0);  // travelled ahead, along +x
  // And backwards: the drag is odd in the speed.
  run(&body, 10.0, axis(0, -thrust));
  EXPECT_NEAR(body.velocity()[0], -expected, 0.005 * expected);
}

// 3a. Positively buoyant by 10 N (rho g V = m g + 10 N): the body rises upright at the speed where the heave
// damping takes the net buoyancy, 10 = Zw w + Zww w^2 (0.158 m/s). Bound 0.5%, as test 2 (exact at a
// steady state). Time constant m'_z / (Zw + 2 Zww w) = 0.35 s; 15 s. Fails with buoyancy along -z (sinks).
TEST(VehicleBody, PositivelyBuoyantBodyRisesAtTheTerminalSpeed)
{
  VehicleParams p = neutral();
  const double lift = 10.0;
  p.displaced_volume = (p.weight() + lift) / (p.water_density * p.gravity);
  VehicleBody body = bodyWith(p);
  run(&body, 15.0, Wrench::Zero());
  const double expected = steadySpeed(lift, p.linear_damping[2], p.quadratic_damping[2]);
  EXPECT_NEAR(body.velocity()[2], expected, 0.005 * expected);
  EXPECT_GT(body.position().z(), 0.9 * expected * 15.0);  // up, in the world
  EXPECT_LT(tilt(body), 1e-9);                            // and upright
}

// 3a'. The same body 10 N light under a water surface (z = 0) floats up to it and settles where the submerged share
// s of its 0.254 m hull carries its weight: s B = W, so its centre of buoyancy (the hull's middle) sits at
// surface + h / 2 - s h. Without the surface's share it kept all of B above the water and rose for good (a reviewer
// saw a BlueROV2 1.6 m above the surface after 60 s). Bound: 1 mm (the step's error at rest is none: the balance is
// exact there; the damping lost above the water only slows the settling). Its potential energy, the integral of
// -s B dz, is continuous across the surface: with no thrust and the water's damping the body ends with less energy
// than it started with (it rose 1 m against a 10 N lift: 10 J to lose; measured, the energy never rose by more
// than 1e-6 J from one step to the next, which is not asserted: the explicit restoring force may add a little near
// the surface's ramp).
TEST(VehicleBody, ALightBodyFloatsAtTheSurfaceWithTheShareThatCarriesItsWeight)
{
  VehicleParams p = neutral();
  const double lift = 10.0;
  p.displaced_volume = (p.weight() + lift) / (p.water_density * p.gravity);
  VehicleBody body = bodyWith(p);
  ASSERT_TRUE(body.setState(Eigen::Vector3d(0.0, 0.0, -1.0), Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  body.setWaterSurface(0.0);
  const double start = body.kineticEnergy() + body.potentialEnergy();
  double energy = start, rise = 0.0;
  for (int k = 0; k < 6000; ++k)  // 60 s
  {
    ThrustUsed used;
    ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), &used).ok);
    const double now = body.kineticEnergy() + body.potentialEnergy();
    rise = std::max(rise, now - energy);
    energy = now;
  }
  std::printf("[ measured ] floating: energy %.4f J from %.4f J, largest rise in a step %.3g J\n", energy, start, rise);
  const double share = p.weight() / p.buoyancy();
  const double centre = body.position().z() + p.center_of_buoyancy.z();
  std::printf("[ measured ] floating: centre of buoyancy at %.5f m (s B = W: %.5f m), share %.4f\n", centre,
              0.5 * p.size.z() - share * p.size.z(), body.submergedShare());
  EXPECT_NEAR(centre, 0.5 * p.size.z() - share * p.size.z(), 1e-3);
  EXPECT_NEAR(body.submergedShare(), share, 1e-3 / p.size.z());
  EXPECT_LT(energy, start);
}

// 3a'''. Out of the water a body has no added mass: it falls at g. The BlueROV2 Heavy 2 m above the surface, from
// rest: nothing but its weight acts (no buoyancy, no damping out of the water), so its heave mass is m alone and
// the step's kick and drift are exact for a constant force: w_n = -g h n, z_n = z_0 - g h^2 n (n + 1) / 2 (bound
// 1e-9 m: rounding over 40 steps). Seen failing with the added mass kept out of the water: it fell at
// g m / (m + Z_wdot), 0.42 g.
TEST(VehicleBody, OutOfTheWaterABodyFallsAtG)
{
  const VehicleParams p;
  VehicleBody body = bodyWith(p);
  const double z0 = 2.0;
  ASSERT_TRUE(body.setState(Eigen::Vector3d(0.0, 0.0, z0), Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  body.setWaterSurface(0.0);
  ASSERT_EQ(body.submergedShare(), 0.0);
  const int steps = 40;
  for (int n = 1; n <= steps; ++n)
  {
    ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    ASSERT_EQ(body.submergedShare(), 0.0) << "step " << n;
  }
  const double fall = p.gravity * kStep * kStep * steps * (steps + 1) / 2.0;
  std::printf("[ measured ] out of the water: fell %.6f m in %.2f s (exact for the step: %.6f m)\n",
              z0 - body.position().z(), steps * kStep, fall);
  EXPECT_NEAR(body.position().z(), z0 - fall, 1e-9);
  EXPECT_NEAR(body.velocity()[2], -p.gravity * kStep * steps, 1e-12);
}

// 3a''''. Entering the water a body keeps its momentum (von Karman's water entry): the added mass it gains slows
// it. A body with no buoyancy (V = 0) and no damping dropped through the surface: only its weight W acts, so its
// momentum M(s) w, M at the share s it ends each step at, grows by W h a step exactly: -W t (within 1e-9 of it,
// relative) through the whole crossing (share 0 to 1), while its speed falls below free fall's. The same through
// startStep, stepped and stepAgain (a VehicleCoupling sub-step's path). Seen failing with the velocity kept
// instead (the added mass gained for nothing: momentum, and kinetic energy, out of nowhere).
TEST(VehicleBody, EnteringTheWaterABodyKeepsItsMomentum)
{
  VehicleParams p;
  p.displaced_volume = 0.0;
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  for (const bool coupled : {false, true})
  {
    SCOPED_TRACE(coupled ? "startStep, stepped, stepAgain" : "step");
    VehicleBody body = bodyWith(p);
    ASSERT_TRUE(
        body.setState(Eigen::Vector3d(0.0, 0.0, 0.5 * p.size.z() + 0.01), Eigen::Quaterniond::Identity(), Twist::Zero())
            .ok);
    body.setWaterSurface(0.0);
    ASSERT_EQ(body.submergedShare(), 0.0);
    double worst = 0.0;
    int n = 0;
    for (; n < 400 && body.submergedShare() < 1.0; ++n)
    {
      if (coupled)
      {
        tryThenStep(body, kStep, Wrench::Zero());
        ASSERT_FALSE(::testing::Test::HasFatalFailure());
      }
      else
      {
        ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
      }
      const double momentum = body.massMatrixAt(body.submergedShare())(2, 2) * body.velocity()[2];
      const double expected = -p.weight() * kStep * (n + 1);
      worst = std::max(worst, std::abs(momentum - expected) / std::abs(expected));
    }
    std::printf("[ measured ] through the surface in %d steps: momentum within %.2g of -W t (relative)\n", n, worst);
    EXPECT_GT(n, 10) << "it crossed the surface in steps";
    EXPECT_EQ(body.submergedShare(), 1.0) << "and ended under water";
    EXPECT_LT(worst, 1e-9);
    EXPECT_GT(body.velocity()[2], -p.gravity * kStep * n) << "slower than free fall";
  }
}

// 3a'''''. Coasting through the surface with nothing acting (no gravity, no buoyancy, no damping): going down, the
// momentum is kept, so fully under water the heave speed is v0 m / (m + Z_wdot) (the product of each step's
// ratio telescopes); going up, the velocity is kept, so it leaves at v0 exactly (1e-12 relative both). With
// the momentum kept both ways it would speed up leaving (kinetic energy out of nowhere); with the velocity kept
// both ways it would not slow entering.
TEST(VehicleBody, CoastingDownThroughTheSurfaceKeepsTheMomentumAndUpTheVelocity)
{
  VehicleParams p;
  p.gravity = 0.0;
  p.displaced_volume = 0.0;
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  const double speed = 0.5;
  for (const double direction : {-1.0, 1.0})
  {
    SCOPED_TRACE(direction < 0.0 ? "down" : "up");
    VehicleBody body = bodyWith(p);
    const double start_z = -direction * (p.size.z() + 0.01);  // a hull's height from the surface, out or under
    ASSERT_TRUE(
        body.setState(Eigen::Vector3d(0.0, 0.0, start_z), Eigen::Quaterniond::Identity(), axis(2, direction * speed))
            .ok);
    body.setWaterSurface(0.0);
    const double from = body.submergedShare();
    for (int n = 0; n < 400; ++n)
    {
      ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    }
    ASSERT_EQ(body.submergedShare(), 1.0 - from) << "through the surface to the other side";
    const double expected = direction < 0.0 ? -speed * p.mass / (p.mass + p.added_mass[2]) : speed;
    std::printf("[ measured ] coasting %s through the surface: %.9f m/s (expected %.9f)\n",
                direction < 0.0 ? "down" : "up", body.velocity()[2], expected);
    EXPECT_NEAR(body.velocity()[2], expected, 1e-12 * speed);
  }
}

// 3a''''''. The momentum is kept with a full mass matrix too (r_G off the origin: M_RB couples heave and pitch). A
// body set at share 0.2 whose surface then rises to put it at share 0.8 (a state set, the surface moved since):
// the next step starts from M(0.8)^-1 M(0.2) nu_r, its momentum kept (1e-12 relative).
TEST(VehicleBody, AStepThatStartsDeeperKeepsTheMomentumWithAFullMassMatrix)
{
  VehicleParams p;
  p.center_of_gravity = Eigen::Vector3d(0.05, 0.0, -0.02);
  VehicleBody body = bodyWith(p);
  ASSERT_FALSE(body.massMatrix().isDiagonal(0.0));
  const double height = p.size.z();
  body.setWaterSurface(0.0);
  // Share s: the centre of buoyancy at h / 2 - s h.
  ASSERT_TRUE(body.setState(Eigen::Vector3d(0.0, 0.0, 0.5 * height - 0.2 * height - p.center_of_buoyancy.z()),
                            Eigen::Quaterniond::Identity(), (Twist() << 0.3, 0.1, -0.4, 0.05, 0.2, -0.1).finished())
                  .ok);
  ASSERT_NEAR(body.submergedShare(), 0.2, 1e-12);
  body.setWaterSurface(0.6 * height);
  ASSERT_NEAR(body.submergedShare(), 0.8, 1e-12);
  VehicleStepStart start;
  ASSERT_TRUE(body.startStep(kStep, &start).ok);
  const Vector6 before = body.massMatrixAt(0.2) * body.relativeVelocity();
  const Vector6 after = body.massMatrixAt(0.8) * start.relative;
  EXPECT_LT((after - before).norm(), 1e-12 * before.norm()) << after.transpose() << " vs " << before.transpose();
  // Its kinetic energy, 1/2 p^T M^-1 p, falls as M grows (the pitch rate may grow through the heave-pitch coupling).
  const double energy_before = 0.5 * body.relativeVelocity().dot(before);
  const double energy_after = 0.5 * start.relative.dot(after);
  std::printf("[ measured ] kinetic energy %.4f J at share 0.2, %.4f J at 0.8 with the momentum kept\n", energy_before,
              energy_after);
  EXPECT_LT(energy_after, energy_before);
}

// 3a''. Thrusters out of the water push nothing. A neutral body at rest with its centre of buoyancy at the surface
// (half its hull out, share 1/2), fully out (share 0) and fully under (share 1), given 100 N of heave thrust for
// one step. From rest the step is exact per axis (nothing turns it: diagonal mass, r_G at the origin, no
// current): the thrust's own velocity change is h s F / (m' + h s Zw), m' = m + s Z_wdot (the added mass of the
// share in the water), the linear damping on that share, taken as the difference from the same step without
// thrust (the restoring force's part cancels). Bound 1e-12 m/s (rounding). The applied thrust is reported as
// s F. Seen failing with the thrust applied whole out of the water (0.031 m/s where none is due at share 0).
TEST(VehicleBody, ThrustersOutOfTheWaterPushNothing)
{
  const VehicleParams p = neutral();
  const double force = 100.0;
  for (const double share : {0.0, 0.5, 1.0})
  {
    const double mass = p.mass + share * p.added_mass[2];
    SCOPED_TRACE(share);
    // The centre of buoyancy (0.01 m above the origin) at surface + h/2 - s h.
    const Eigen::Vector3d where(0.0, 0.0, 0.5 * p.size.z() - share * p.size.z() - p.center_of_buoyancy.z());
    double rise[2];
    for (int pushed = 0; pushed < 2; ++pushed)
    {
      VehicleBody body = bodyWith(p);
      ASSERT_TRUE(body.setState(where, Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
      body.setWaterSurface(0.0);
      ASSERT_NEAR(body.submergedShare(), share, 1e-12);
      // The step's velocity at the share it started at (stepped's trial): after it, the body is set for the share
      // it moved to (its momentum kept where that is deeper), which the kick's figure is not about.
      VehicleStepStart start;
      ASSERT_TRUE(body.startStep(kStep, &start).ok);
      VehicleStepTrial trial;
      Eigen::Vector3d position;
      Eigen::Quaterniond attitude;
      ASSERT_TRUE(body.stepped(start, axis(2, pushed * force), Wrench::Zero(), &position, &attitude, &trial).ok);
      EXPECT_NEAR(trial.used.applied[2], pushed * share * force, 1e-12);
      rise[pushed] = trial.turned[2];
    }
    const double expected = kStep * share * force / (mass + kStep * share * p.linear_damping[2]);
    EXPECT_NEAR(rise[1] - rise[0], expected, 1e-12);
  }
}

// 3b. Rolled 30 degrees and let go (neutral, r_B 0.01 m above r_G): the restoring moment B BG sin(phi) rights
// it. Bound: a pendulum of stiffness B BG = 1.32 N m on I' = Ix - K_pdot = 0.449 kg m^2 (omega_n 1.72 rad/s)
// with quadratic roll damping Kpp only (Kp = 0) loses (8/3) Kpp A^3 omega_n^2 per cycle (harmonic balance),
// so its amplitude falls as A0 / (1 + c A0 t), c = (8/3) Kpp omega_n / (2 pi I') = 1.93 1/(rad s): 1.4
// degrees at 20 s. Asserted: below 3 degrees over 20-30 s (twice that, for the harmonic-balance
// approximation), and no tilt beyond the release angle at any time. Fails with r_B and r_G swapped or
// buoyancy along -z (it capsizes to 180 degrees) and with the roll damping left out (amplitude stays 30).
TEST(VehicleBody, RolledBodyRightsItself)
{
  VehicleBody body = bodyWith(neutral());
  const double released = 30.0 * kPi / 180.0;
  ASSERT_TRUE(
      body.setState({0, 0, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(released, Eigen::Vector3d::UnitX())), Twist::Zero())
          .ok);
  double largest_late = 0.0;
  for (int n = 1; n <= 3000; ++n)
  {
    ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    ASSERT_LE(tilt(body), released + 1e-9) << "t " << n * kStep;
    if (n * kStep >= 20.0)
    {
      largest_late = std::max(largest_late, tilt(body));
    }
  }
  EXPECT_LT(largest_late, 3.0 * kPi / 180.0);
}

// 3c. Static heel under a constant roll moment K = 0.5 N m: the restoring moment balances it where
// K = (r_B - r_G) B sin(phi) (22.2 degrees; r_G at the origin, BG = 0.01 m, B = W = 132 N). Bound 2% (the
// issue's); the split is exact at rest (kick: K + restoring = 0). A linear roll damping Kp = 2 N m s is
// added so the heel settles within the run (time constant 2 I' / Kp = 0.45 s; 20 s); it does not enter the
// balance. Fails with BG's sign flipped or the moment arm taken in NED (heel 180 - 22 degrees).
TEST(VehicleBody, StaticHeelMatchesTheRestoringMoment)
{
  VehicleParams p = neutral();
  p.linear_damping[3] = 2.0;
  VehicleBody body = bodyWith(p);
  const double moment = 0.5;
  run(&body, 20.0, axis(3, moment));
  const double metacentric = (p.center_of_buoyancy - p.center_of_gravity).z();
  const double expected = std::asin(moment / (metacentric * p.buoyancy()));
  const Eigen::AngleAxisd turned(body.attitude());
  EXPECT_NEAR(turned.angle(), expected, 0.02 * expected);
  EXPECT_NEAR(std::abs(turned.axis().x()), 1.0, 1e-9);  // about x only
  EXPECT_GT(turned.axis().x() * turned.angle(), 0.0);   // a positive moment heels it the positive way
}

// 4. Rotation. A constant yaw moment N = 1 N m gives the steady yaw rate where N = Nr r + Nrr r|r| (Nr = 0:
// 0.816 rad/s); a couple of two lateral forces of 5 N at x = +-0.2 m, given as the external wrench r x F,
// gives N = 2 N m and 1.155 rad/s. Bound 0.5%, exact at a steady state (test 2; a spin about a principal
// axis has no Coriolis moment). Time constant I'z' / (2 Nrr r) = 0.24 s; 10 s. Fails with the external
// moment dropped or the thrust and external wrench in each other's place with a saturation (none here).
TEST(VehicleBody, ConstantYawMomentGivesTheDampingBalanceRate)
{
  const VehicleParams p = neutral();
  VehicleBody body = bodyWith(p);
  run(&body, 10.0, axis(5, 1.0));
  EXPECT_NEAR(body.velocity()[5], steadySpeed(1.0, p.linear_damping[5], p.quadratic_damping[5]),
              0.005 * steadySpeed(1.0, p.linear_damping[5], p.quadratic_damping[5]));

  VehicleBody couple = bodyWith(p);
  const Eigen::Vector3d force(0.0, 5.0, 0.0);
  const Eigen::Vector3d ahead(0.2, 0.0, 0.0);
  Wrench external = Wrench::Zero();
  external.tail<3>() = ahead.cross(force) + (-ahead).cross(-force);
  run(&couple, 10.0, Wrench::Zero(), external);
  const double expected = steadySpeed(2.0, p.linear_damping[5], p.quadratic_damping[5]);
  EXPECT_NEAR(couple.velocity()[5], expected, 0.005 * expected);
  EXPECT_LT(couple.velocity().head<3>().norm(), 1e-9);  // no net force: it turns on the spot
  EXPECT_LT(tilt(couple), 1e-9);                        // about z only
}

// 5. Energy, thrust off, no current, damping on, buoyancy = weight: the body tumbles from a rolled and
// pitched attitude with every velocity set, and E = 1/2 nu^T M nu + W z_G - B z_B never increases beyond the
// split's step error. Bound per step, from the split (vehicle_body.hpp): the Coriolis step keeps the kinetic
// energy exactly and the damping step only removes it; the kick by the restoring wrench f and the drift
// cancel to first order, leaving at most h^2 (k |omega'|^2 / 2 + |f| |M^-1 (C(nu) nu + D(nu) nu)|)
// (k = B |r_B - r_G| bounds the potential's Hessian in a rotation; the second term is the velocity change
// between kick and drift), taken twice for the O(h^3) rest. And the energy falls to below 2% of its start in
// 60 s. Fails with the damping's sign flipped, with the restoring moment's sign flipped (an O(h) gain per
// step).
TEST(VehicleBody, EnergyNeverIncreasesWithoutThrust)
{
  VehicleParams p = neutral();
  p.center_of_gravity = Eigen::Vector3d(0.02, -0.01, -0.02);  // off the origin: M_RB couples
  p.center_of_buoyancy = Eigen::Vector3d(0.02, -0.01, 0.0);
  VehicleBody body = bodyWith(p);
  const Eigen::Quaterniond start = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                   Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()) *
                                   Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX());
  Twist nu;
  nu << 0.5, -0.3, 0.2, 1.0, -0.8, 1.5;
  ASSERT_TRUE(body.setState({0, 0, -5}, start, nu).ok);
  const Matrix6 mass = body.massMatrix();
  const Matrix6 inverse = mass.inverse();
  const double k = p.buoyancy() * (p.center_of_buoyancy - p.center_of_gravity).norm();
  const double start_energy = body.kineticEnergy() + body.potentialEnergy();
  double energy = start_energy;
  for (int n = 1; n <= 6000; ++n)
  {
    const Twist v = body.velocity();
    const Vector6 momentum = mass * v;
    Vector6 coriolis;
    coriolis.head<3>() = v.tail<3>().cross(momentum.head<3>());
    coriolis.tail<3>() = v.head<3>().cross(momentum.head<3>()) + v.tail<3>().cross(momentum.tail<3>());
    const Vector6 damping = (p.linear_damping + p.quadratic_damping.cwiseProduct(v.cwiseAbs())).cwiseProduct(v);
    const double restoring = body.restoringWrench().norm();
    ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    const double turn = body.velocity().tail<3>().squaredNorm();
    const double allowance =
        2.0 * kStep * kStep * (0.5 * k * turn + restoring * (inverse * (coriolis + damping)).norm());
    const double next = body.kineticEnergy() + body.potentialEnergy();
    ASSERT_LE(next, energy + allowance + 1e-12 * start_energy)
        << "t " << n * kStep << ": gained " << next - energy << " J, allowed " << allowance;
    energy = next;
  }
  // The lowest energy is upright at rest: W z_G - B z_B = -B |r_B - r_G| + (W - B) z = -k at this depth.
  const double rest = -k + (p.weight() - p.buoyancy()) * body.position().z();
  EXPECT_LT(energy - rest, 0.02 * (start_energy - rest));
}

// 5b. The Coriolis and centripetal terms are Kirchhoff's: a free body in still water (no damping, no
// restoring wrench: r_B = r_G, B = W) keeps its impulse, body and entrained water together, in the world
// frame: P = R p1 and L = R p2 + x cross R p1 with [p1; p2] = M nu. With unequal added masses a generic start
// tumbles (the Munk moment), so P and L are kept only through C(nu). For a free body the split is second
// order (the Coriolis step is the implicit midpoint rule to one fixed-point pass, the drift uses the same
// mean velocity and the half-way attitude): halving h quarters the drift over 10 s (ratio 4 within 20%, the
// higher-order rest), and at h = 0.01 s it stays below 0.1% of |P| and of |L| + max |x| |P|. Fails with C's
// sign flipped or a block of C missing (P turns by O(1), and the drift does not shrink with h), and with C
// frozen at the step's start only (first order: ratio 2, 16% drift).
TEST(VehicleBody, FreeBodyKeepsItsImpulse)
{
  const VehicleParams p = freeBody();
  const Twist nu = spinning();
  const auto impulse = [](const VehicleBody& body, Eigen::Vector3d* linear, Eigen::Vector3d* angular)
  {
    const Vector6 momentum = body.massMatrix() * body.velocity();
    *linear = body.attitude() * momentum.head<3>();
    *angular = body.attitude() * momentum.tail<3>() + body.position().cross(*linear);
  };
  double drift[2] = {0.0, 0.0};
  for (int refinement = 0; refinement < 2; ++refinement)
  {
    VehicleBody body = bodyWith(p);
    ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), nu).ok);
    Eigen::Vector3d linear0, angular0;
    impulse(body, &linear0, &angular0);
    const double h = kStep / (1 << refinement);
    for (int n = 0; n < static_cast<int>(std::lround(10.0 / h)); ++n)
    {
      ASSERT_TRUE(body.step(h, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
      Eigen::Vector3d linear, angular;
      impulse(body, &linear, &angular);
      const double scale = angular0.norm() + body.position().norm() * linear0.norm();
      drift[refinement] = std::max(
          {drift[refinement], (linear - linear0).norm() / linear0.norm(), (angular - angular0).norm() / scale});
    }
    EXPECT_NEAR(body.kineticEnergy(), 0.5 * nu.dot(body.massMatrix() * nu), 1e-9);  // the Cayley step keeps it
  }
  EXPECT_LT(drift[0], 1e-3);
  EXPECT_NEAR(drift[0] / drift[1], 4.0, 0.8) << "drift " << drift[0] << " at h, " << drift[1] << " at h/2";
}

// stepAgain() (the dynamic vehicle end's second step: predict()'s trial taken again with the tether's pull) against
// step() with the same total wrench. A free body (no damping, no restoring wrench) spinning and moving, under
// a force at an offset (its moment turning it), for 2 s. The two differ only in part 3's C argument: step()
// takes two passes from nu_r' (the second from the first's end: C's argument off by O(h^2)), stepAgain() one
// from the trial's first pass moved by the added wrench (also off by O(h^2)), so their difference at the end
// is second order: at h / 2 a quarter of that at h (asserted: at most a third; a first-order guess, C at
// nu_r' alone, gives a half). Size: below step()'s own error at h (against step() at h / 64), which is
// first order: the difference is not what limits the accuracy. And the Cayley property: with no wrench and no
// damping stepAgain() keeps the kinetic energy (1e-9 J, rounding).
TEST(VehicleBody, StepAgainIsTheWholeStepWithTheAddedWrench)
{
  const VehicleParams p = freeBody();
  const Twist nu = spinning();
  const Eigen::Vector3d offset(-0.2, 0.1, 0.05), force(-30.0, 10.0, 5.0);
  Wrench more;
  more << force, offset.cross(force);
  const double duration = 2.0;
  const auto whole = [&](double h)
  {
    VehicleBody body = bodyWith(p);
    EXPECT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), nu).ok);
    for (int n = 0; n < static_cast<int>(std::lround(duration / h)); ++n)
    {
      EXPECT_TRUE(body.step(h, Wrench::Zero(), more, nullptr).ok);
    }
    return Twist(body.velocity());
  };
  const auto again = [&](double h)
  {
    VehicleBody body = bodyWith(p);
    EXPECT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), nu).ok);
    for (int n = 0; n < static_cast<int>(std::lround(duration / h)); ++n)
    {
      tryThenStep(body, h, more);
    }
    return Twist(body.velocity());
  };
  const double difference = (whole(kStep) - again(kStep)).norm();
  const double difference_half = (whole(kStep / 2) - again(kStep / 2)).norm();
  const double own_error = (whole(kStep) - whole(kStep / 64)).norm();
  std::printf(
      "[ measured ] stepAgain vs step at h = %g s: %.3g m/s apart after %g s (%.3g at h/2); step()'s own "
      "error %.3g m/s\n",
      kStep, difference, duration, difference_half, own_error);
  EXPECT_LT(difference, own_error) << "difference " << difference << " m/s, step()'s own error " << own_error;
  EXPECT_GT(difference / difference_half, 3.0)
      << "difference " << difference << " at h, " << difference_half << " at h/2";

  VehicleBody body = bodyWith(p);
  ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), nu).ok);
  const double energy = body.kineticEnergy();
  for (int n = 0; n < 1000; ++n)
  {
    tryThenStep(body, kStep, Wrench::Zero());
  }
  EXPECT_NEAR(body.kineticEnergy(), energy, 1e-9);
  Wrench bad = Wrench::Zero();
  bad[2] = std::nan("");
  VehicleStepStart start;
  ASSERT_TRUE(body.startStep(kStep, &start).ok);
  const Twist before = body.velocity();
  EXPECT_FALSE(body.stepAgain(start, VehicleStepTrial{}, bad).ok);
  EXPECT_EQ(body.velocity(), before);
}

// The rigid body about an origin off its centre of gravity (Fossen 2011, ch. 3): a couple N on a free
// body at rest (no added mass, no damping, no restoring wrench) turns it about its centre of gravity with its
// inertia there: after one step h, dw = h I_G^-1 N and the centre of gravity has not moved (dv + dw x r_G =
// 0, the origin's velocity when the CG is still). Exact for the kick; the Coriolis step then acts on a
// velocity of order h N / I, changing it by a relative 1e-4 at most here (asserted: 1e-3). Fails with the
// parallel-axis term -m S(r_G)^2 left out of M_RB (dw 5% off) or the coupling blocks' signs swapped.
TEST(VehicleBody, CoupleTurnsAFreeBodyAboutItsCentreOfGravity)
{
  VehicleParams p;
  p.added_mass.setZero();
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  p.displaced_volume = p.mass / p.water_density;
  p.center_of_gravity = Eigen::Vector3d(0.1, -0.05, 0.04);
  p.center_of_buoyancy = p.center_of_gravity;
  VehicleBody body = bodyWith(p);
  const Eigen::Vector3d couple(0.3, -0.2, 0.5);
  Wrench external = Wrench::Zero();
  external.tail<3>() = couple;
  ASSERT_TRUE(body.step(kStep, Wrench::Zero(), external, nullptr).ok);
  const Eigen::Vector3d turn = body.velocity().tail<3>();
  const Eigen::Vector3d expected = kStep * p.inertia.cwiseInverse().cwiseProduct(couple);
  EXPECT_LT((turn - expected).norm(), 1e-3 * expected.norm()) << turn.transpose() << " vs " << expected.transpose();
  const Eigen::Vector3d centre_velocity = body.velocity().head<3>() + turn.cross(p.center_of_gravity);
  EXPECT_LT(centre_velocity.norm(), 1e-3 * turn.norm() * p.center_of_gravity.norm());
}

// A free body spinning about a principal axis through its centre of gravity (freeBody(): r_G = r_B = 0)
// keeps its rate (C(nu) nu = [0; w x I w] = 0 for w along a principal axis), so after N steps its attitude is
// the turn by w N h about that axis, exactly up to rounding (1e-12 rad over 200 steps of ~1e-16 each). Three
// rates: 2 and 12 rad/s (0.02 and 0.12 rad a step, turned by the short series) and 40 rad/s (0.4 rad a step,
// by sine and cosine); fails if either way of turning the attitude is wrong (the series' x^4 term or the half
// angle off; its higher terms move a step's turn by less than rounding does).
TEST(VehicleBody, SpinAboutAPrincipalAxisTurnsByRateTimesTime)
{
  for (const double rate : {2.0, 12.0, 40.0})
  {
    VehicleBody body = bodyWith(freeBody());
    Twist nu = Twist::Zero();
    nu[5] = rate;
    ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond::Identity(), nu).ok);
    const int steps = 200;
    for (int i = 0; i < steps; ++i)
    {
      ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    }
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(rate * steps * kStep, Eigen::Vector3d::UnitZ()));
    EXPECT_LT(body.attitude().angularDistance(expected), 1e-12) << "at " << rate << " rad/s";
    EXPECT_NEAR(body.velocity()[5], rate, 1e-12 * rate);
    EXPECT_LT(body.position().norm(), 1e-12);
  }
}

// The attitude stays a unit quaternion over a long tumble. Each step multiplies it by two unit quaternions
// (rounding leaves |q|^2 = 1 + e, |e| a few ulp) and renormalises it by one Newton step for 1 / sqrt(|q|^2),
// which leaves e^2 (1e-31) plus that step's own rounding: | |q| - 1 | stays within a few ulp at every step,
// bounded here by 4 epsilon (8.9e-16), instead of random-walking (sqrt(n) ulp: 7e-14 after the 1e5 steps).
// Tumbling about all three axes, at 1.6 rad/s (the small turns' series) and at 40 rad/s (sincos). Fails with
// the renormalisation left out.
TEST(VehicleBody, AttitudeStaysAUnitQuaternionOverALongTumble)
{
  for (const double scale : {1.0, 25.0})
  {
    VehicleBody body = bodyWith(freeBody());
    Twist nu = spinning();
    nu.tail<3>() *= scale;
    ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond(0.8, 0.0, 0.6, 0.0), nu).ok);
    double worst = 0.0;
    for (int i = 0; i < 100000; ++i)
    {
      ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
      worst = std::max(worst, std::abs(body.attitude().norm() - 1.0));
    }
    EXPECT_LE(worst, 4.0 * std::numeric_limits<double>::epsilon()) << "at " << scale << " x the spin";
  }
}

// 6. Current: a body at rest in a uniform current of 0.4 m/s along world x drifts to the current's velocity.
// The water moves past it at -0.4 m/s relative; with no Coriolis coupling for a flow along a principal axis,
// the relative speed decays as in test 1 (same closed form and bound): the body's speed over ground is the
// current's minus it. Heading along the current: relative flow in surge; turned 90 degrees (heading world
// +y): in sway, where Yv = 0 and the split is exact for pure quadratic damping (1/v is linear in t for both).
// Fails with the current's rotation into the body frame left out (the turned body drifts in sway the wrong
// way, or not at all) and with the damping on the absolute velocity (it never moves).
TEST(VehicleBody, BodyInACurrentDriftsWithIt)
{
  const VehicleParams p = neutral();
  const Eigen::Vector3d current(0.4, 0.0, 0.0);
  for (const double heading : {0.0, kPi / 2.0})
  {
    VehicleBody body = bodyWith(p);
    ASSERT_TRUE(body.setCurrent(current).ok);
    ASSERT_TRUE(body.setState({0, 0, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ())),
                              Twist::Zero())
                    .ok);
    const int axis_index = heading == 0.0 ? 0 : 1;
    const double m = p.mass + p.added_mass[axis_index];
    const double a = p.linear_damping[axis_index];
    const double b = p.quadratic_damping[axis_index];
    const double u0 = current.norm();
    for (int n = 1; n <= 3000; ++n)
    {
      ASSERT_TRUE(body.step(kStep, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
      const double t = n * kStep;
      const double relative = decay(u0, a, b, m, t);  // the water's speed past the body
      const Eigen::Vector3d over_ground = body.attitude() * body.velocity().head<3>();
      const double lag = u0 - over_ground.x();  // = the relative speed
      ASSERT_GE(lag - relative, -1e-9) << "heading " << heading << ", t " << t;
      ASSERT_LE(lag - relative, 0.5 * kStep * (a / m) * (u0 - relative) + 1e-9) << "heading " << heading << ", t " << t;
      ASSERT_LT(std::abs(over_ground.y()) + std::abs(over_ground.z()), 1e-9);
    }
    // 30 s on: within 2% of the current (the slower, sway, case is at 0.4 / (1 + b u0 t / m') = 1.2%).
    const Eigen::Vector3d over_ground = body.attitude() * body.velocity().head<3>();
    EXPECT_NEAR(over_ground.x(), current.x(), 0.02 * current.x()) << "heading " << heading;
  }
}

// 7. Saturation: a command beyond the limit is held at it and reported, never silently: the step says which
// thrust it applied and which axes it held. 500 N of surge (limit 113.7 N) and -100 N m of yaw (limit 30.4
// N m) apply +113.7 N and -30.4 N m; the speed reached is the limit's drag balance (test 2), not the
// command's. A command within the limits is applied as given, nothing reported.
TEST(VehicleBody, ThrustBeyondTheLimitIsHeldAtItAndReported)
{
  const VehicleParams p = neutral();
  VehicleBody body = bodyWith(p);
  Wrench command = Wrench::Zero();
  command[0] = 500.0;
  command[5] = -100.0;
  ThrustUsed used;
  ASSERT_TRUE(body.step(kStep, command, Wrench::Zero(), &used).ok);
  EXPECT_TRUE(used.saturated());
  EXPECT_EQ(used.saturated_axes, (1u << 0) | (1u << 5));
  EXPECT_DOUBLE_EQ(used.applied[0], p.thrust_limit[0]);
  EXPECT_DOUBLE_EQ(used.applied[5], -p.thrust_limit[5]);
  EXPECT_EQ(used.applied.segment<4>(1), Vector6::Zero().segment<4>(1));
  run(&body, 10.0, axis(0, 500.0));
  const double expected = steadySpeed(p.thrust_limit[0], p.linear_damping[0], p.quadratic_damping[0]);
  EXPECT_NEAR(body.velocity()[0], expected, 0.005 * expected);

  Wrench within = Wrench::Zero();
  within << 50.0, -20.0, 100.0, 5.0, -5.0, 10.0;
  ASSERT_TRUE(body.step(kStep, within, Wrench::Zero(), &used).ok);
  EXPECT_FALSE(used.saturated());
  EXPECT_EQ(used.applied, within);
}

// Bad input is refused with a message and leaves the state as it was.
TEST(VehicleBody, BadInputIsRefusedAndChangesNothing)
{
  VehicleBody body;
  ASSERT_TRUE(body.setState({1, 2, 3}, Eigen::Quaterniond::Identity(), axis(0, 0.5)).ok);
  const Twist before = body.velocity();
  ThrustUsed used;
  Wrench nan_thrust = Wrench::Zero();
  nan_thrust[2] = std::nan("");
  const Status refused = body.step(kStep, nan_thrust, Wrench::Zero(), &used);
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.message.find("finite"), std::string::npos) << refused.message;
  EXPECT_FALSE(body.step(0.0, Wrench::Zero(), Wrench::Zero(), &used).ok);
  EXPECT_FALSE(body.step(-kStep, Wrench::Zero(), Wrench::Zero(), &used).ok);
  const Status too_long = body.step(2.0 * body.stableStepLimit(), Wrench::Zero(), Wrench::Zero(), &used);
  EXPECT_FALSE(too_long.ok);
  EXPECT_NE(too_long.message.find("stability limit"), std::string::npos) << too_long.message;
  EXPECT_FALSE(body.setCurrent({0.0, std::nan(""), 0.0}).ok);
  EXPECT_FALSE(body.setState({0, 0, 0}, Eigen::Quaterniond(0, 0, 0, 0), Twist::Zero()).ok);
  VehicleParams negative;
  negative.mass = -1.0;
  EXPECT_FALSE(body.setParams(negative).ok);
  EXPECT_EQ(body.params().mass, VehicleParams().mass);
  EXPECT_EQ(body.velocity(), before);
  EXPECT_EQ(body.position(), Eigen::Vector3d(1, 2, 3));
}

// The stated stability limit (vehicle_body.hpp): 2 / sqrt(k / I') for the restoring spring, 1.05 s for the
// BlueROV2 Heavy (k = B |r_B - r_G| = 1.31 N m on the smallest effective inertia, pitch: I' = Iy - M_qdot =
// 0.365 kg m^2). Just inside it (0.95 of it) a pitched body stays bounded for 2000 steps: semi-implicit
// Euler on a spring keeps a modified energy, so the tilt stays below 0.2 / sqrt(1 - (0.95)^2) = 0.64 rad
// (asserted: 1 rad); beyond the limit the same map grows geometrically, and the step is refused.
TEST(VehicleBody, StepLimitIsTheRestoringSpringsAndHolds)
{
  const VehicleParams p;
  VehicleBody body = bodyWith(p);
  const double k = p.buoyancy() * (p.center_of_buoyancy - p.center_of_gravity).norm();
  const double pitch_inertia = p.inertia[1] + p.added_mass[4];
  EXPECT_NEAR(body.stableStepLimit(), 2.0 / std::sqrt(k / pitch_inertia), 1e-9);
  ASSERT_TRUE(
      body.setState({0, 0, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())), Twist::Zero()).ok);
  const double h = 0.95 * body.stableStepLimit();
  for (int n = 0; n < 2000; ++n)
  {
    ASSERT_TRUE(body.step(h, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    ASSERT_LT(tilt(body), 1.0) << "step " << n;
  }
  EXPECT_FALSE(body.step(1.01 * body.stableStepLimit(), Wrench::Zero(), Wrench::Zero(), nullptr).ok);
}

// With a water surface the hull crossing it is a heave spring the step takes explicitly: its buoyancy s B falls
// with the share s in the water, k = B / size.z, on the heave mass m + s Z_wdot, at least m (out of the water; and
// its thrust likewise). The BlueROV2 Heavy made twice as light as it is heavy (B = 2 W: it floats with half its
// height out, mid-way through the ramp), its damping taken away (the implicit damping steadies any step): the
// heave spring on the mass out of the water (8.79 rad/s) needs h < 2 / omega = 0.23 s, where the restoring
// moment's limit under water is 0.74 s. stableStepLimitAt(surface) is at most that, and stableStepLimit() is it
// once the body has a surface (and the limit under water again without). Started 2 cm below where it floats and
// stepped at 0.95 of the limit for 2000 steps, the heave stays within semi-implicit Euler's modified energy's
// bound, A / sqrt(1 - (h omega / 2)^2) < A / sqrt(1 - 0.95^2) = 3.2 A (omega at most the dry one); beyond the
// limit the step is refused, naming the surface. Seen failing with the surface left out of the limit: stepped at
// 0.95 of the restoring moment's limit, the first step overshoots out of the ramp (0.41 m off, 20-fold).
TEST(VehicleBody, StepLimitWithASurfaceHoldsTheHullCrossingIt)
{
  VehicleParams p;
  p.displaced_volume = 2.0 * p.mass / p.water_density;
  p.linear_damping.setZero();
  p.quadratic_damping.setZero();
  VehicleBody body = bodyWith(p);
  const double under_water = body.stableStepLimit();
  const double omega = std::sqrt(p.buoyancy() / p.size.z() / p.mass);  // the heave spring on the mass out of the water
  const double limit = body.stableStepLimitAt(0.0);
  std::printf("[ measured ] step limit under water %.4f s, with the surface %.4f s; the heave spring's own %.4f s\n",
              under_water, limit, 2.0 / omega);
  EXPECT_LE(limit, 2.0 / omega);
  EXPECT_LT(limit, under_water);
  // Floating: s B = W at s = 1/2, the centre of buoyancy at the surface; the body 2 cm below that.
  const double drop = 0.02;
  const Eigen::Vector3d floating(0.0, 0.0, -p.center_of_buoyancy.z());
  ASSERT_TRUE(
      body.setState(floating - Eigen::Vector3d(0.0, 0.0, drop), Eigen::Quaterniond::Identity(), Twist::Zero()).ok);
  body.setWaterSurface(0.0);
  EXPECT_EQ(body.stableStepLimit(), limit);
  const double h = 0.95 * body.stableStepLimit();
  double largest = 0.0;
  for (int n = 0; n < 2000; ++n)
  {
    ASSERT_TRUE(body.step(h, Wrench::Zero(), Wrench::Zero(), nullptr).ok);
    largest = std::max(largest, std::abs(body.position().z() - floating.z()));
    ASSERT_LT(largest, drop / std::sqrt(1.0 - 0.95 * 0.95)) << "step " << n;
  }
  std::printf("[ measured ] heave at most %.4f m from where it floats (started %.2f m off)\n", largest, drop);
  const Status beyond = body.step(1.01 * body.stableStepLimit(), Wrench::Zero(), Wrench::Zero(), nullptr);
  EXPECT_FALSE(beyond.ok);
  EXPECT_NE(beyond.message.find("surface"), std::string::npos) << beyond.message;
  body.setWaterSurface(std::nan(""));
  EXPECT_EQ(body.stableStepLimit(), under_water);
}

}  // namespace
}  // namespace rov_tether::test
