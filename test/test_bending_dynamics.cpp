// Bending dynamics against closed forms (issue 24): the transverse natural frequencies of a tensioned beam,
// from a string to a beam, and of a beam with no tension at all, with the default bending stiffness,
// segment length and step, and Morison added mass. docs/references.md, "A tensioned beam's modes".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/study/study.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

/// A straight cable of `length` [m] between the spool at the origin and a vehicle on the x axis, stretched
/// by `strain`, weightless in water, with added mass and no drag: the default bending_stiffness (0.2 N m^2),
/// segment_length (0.1 m), time_step (5 ms) and solver (direct).
TetherParams beamParams(double length, double axial_stiffness)
{
  TetherParams p;
  p.cable_length = length;
  p.initial_deployed_length = length;
  p.min_deployed_length = p.segment_length;
  p.winch_mode = WinchMode::kLocked;
  p.noise = 0.0;
  p.weight_in_water = 0.0;
  p.drag_model = DragModel::kMorison;  // added mass across the cable, Ca rho pi d^2 / 4 = 0.322 kg/m
  p.normal_drag_coefficient = 0.0;     // a free oscillation: nothing damps it but the step itself
  p.tangential_drag_coefficient = 0.0;
  p.axial_stiffness = axial_stiffness;
  return p;
}

struct Modes
{
  double measured[3];  ///< [rad/s] modes 1-3
  double expected[3];  ///< [rad/s] the closed form
};

/// Pins a `length` [m] cable between supports `span` apart, jogs the vehicle end 0.1 mm sideways in one step,
/// and measures modes 1-3 from the upward zero crossings of their modal coordinates
/// q_n = sum_k (y_k - y_line(k)) sin(n pi k / N), k over the inner particles: the discrete pinned-pinned
/// beam's modes are these sines exactly (its stiffness is T D + EI D^2 / dL^3 with D the second difference,
/// whose eigenvectors they are), so each q_n is one mode alone, whatever the jog excites.
Modes measureModes(double length, double tension, double axial_stiffness)
{
  const TetherParams p = beamParams(length, axial_stiffness);
  const double span = length * (1.0 + tension / axial_stiffness);
  const double mu = p.effectiveMassPerLength() * length / span;  // [kg/m] of span, added mass included
  const double ei = p.bending_stiffness;
  Modes m{};
  double slowest = 0.0;
  for (int n = 1; n <= 3; ++n)
  {
    // Pinned ends: omega_n = (n pi / L) sqrt(T / mu) sqrt(1 + (EI / T) (n pi / L)^2), written so T = 0
    // (a beam: omega_n = (n pi / L)^2 sqrt(EI / mu)) is the same formula.
    const double k = n * kPi / span;
    m.expected[n - 1] = k * std::sqrt((tension + ei * k * k) / mu);
    slowest = std::max(slowest, 2.0 * kPi / m.expected[n - 1]);
  }
  const double h = p.time_step;
  const double jog = 1e-4;  // [m]
  Tether sim(p, Position::Zero(), Position(span, 0.0, 0.0));
  EXPECT_TRUE(sim.addVehicleSample(h, Position(span, jog, 0.0)).ok);
  const double duration = 3.5 * slowest;  // three upward crossings of the slowest mode at least
  EXPECT_TRUE(sim.addVehicleSample(duration + h, Position(span, jog, 0.0)).ok);
  const std::size_t particles = sim.deployedParticleCount();
  const double segments = static_cast<double>(particles - 1);
  study::CrossingCounter counters[3];
  while (sim.time() < duration)
  {
    sim.step();
    for (int n = 1; n <= 3; ++n)
    {
      double q = 0.0;
      for (std::size_t i = 1; i + 1 < particles; ++i)
      {
        const double s = static_cast<double>(i) / segments;
        q += (sim.particle(i).y() - jog * s) * std::sin(n * kPi * s);
      }
      counters[n - 1].add(sim.time(), q);
    }
  }
  for (int n = 0; n < 3; ++n)
  {
    m.measured[n] = 2.0 * kPi / counters[n].period();
  }
  return m;
}

// A tensioned beam's first three transverse frequencies within 2% of the closed form for pinned ends, from
// string to beam: EI / (T L^2) = 1e-4, 1e-2 and 1, and a beam with no tension. Both ends are pins: the spool
// is a hinge (no bending joint at the spool particle) and so is the vehicle end. A clamp at either end
// would raise a beam's first mode by 56% (clamped-pinned, 15.42 / pi^2) and fail the bending-dominated rows;
// missing added mass would double every frequency, a wrong EI would move the last two rows.
// Where the 2% comes from (the bound), and what the discretisation takes of it: the discrete
// modes are low by (n pi dL / 2L)^2 / 6 on the string part and twice that on the bending part (0.8% at
// mode 3 with 30 segments), and the implicit step by (omega h)^2 / 3 (0.15% at most here); the 0.1 mm jog
// (its largest modal amplitude q = 2 jog / pi) changes the tension by EA (q n pi / L)^2 / 4: under 1e-5 of T
// in the tensioned rows (EA = 1e3 T), and 5e-4 of the beam's EI (pi / L)^2 with EA 1e5 N (a 1 mm jog, ten
// times this one, measured mode 1 3.8% high: the beam is stiffened by its own stretch).
TEST(BendingDynamics, TensionedBeamModesMatchTheClosedForm)
{
  struct Row
  {
    double beta;    ///< EI / (T L^2)
    double length;  ///< [m]
  };
  const double ei = TetherParams().bending_stiffness;
  for (const Row& row : {Row{1e-4, 7.0}, Row{1e-2, 5.0}, Row{1.0, 3.0}, Row{INFINITY, 3.0}})
  {
    const double tension = ei / (row.beta * row.length * row.length);  // 0 for the beam
    // A strain of 1e-3 sets the tension (the beam: EA 1e5 N, the default, and no strain).
    const double axial_stiffness = tension > 0.0 ? 1e3 * tension : 1e5;
    const Modes m = measureModes(row.length, tension, axial_stiffness);
    for (int n = 0; n < 3; ++n)
    {
      const double error = m.measured[n] / m.expected[n] - 1.0;
      std::printf(
          "[ measured ] tensioned beam EI/(T L^2) = %g, L = %.0f m, T = %.4g N: mode %d %.4f rad/s, "
          "closed form %.4f, error %+.2f%%\n",
          row.beta, row.length, tension, n + 1, m.measured[n], m.expected[n], 100.0 * error);
      EXPECT_LT(std::abs(error), 0.02) << "EI/(T L^2) = " << row.beta << ", mode " << n + 1;
    }
  }
}

}  // namespace
}  // namespace rov_tether::test
