#pragma once
// Reference cases of docs/references.md and the speed-against-accuracy study. ROS-free; used by the
// rov_tether_study tool (CSV for the charts) and by the tests that pin its findings.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "rov_tether/core/tether_params.hpp"

namespace rov_tether::study
{

/**
 * Irvine's elastic catenary (docs/references.md "Statics"): end A at (0, 0), end B at (span, 0) (level
 * supports), unstretched length L, weight w per unstretched metre [N/m], axial stiffness EA [N]
 * (infinity: inextensible). Solved by Newton on H, V_A = -w L / 2.
 */
struct Catenary
{
  double length = 10.0;      ///< L [m]
  double weight = 1.0;       ///< w [N/m]
  double stiffness = 1e300;  ///< EA [N]
  double horizontal = 0.0;   ///< H [N]
  double vertical = 0.0;     ///< V_A [N] (negative: A carries half the weight upwards)

  /// Solves for level supports `span` apart; false when Newton does not converge.
  bool solve(double span);
  double x(double s) const;        ///< Horizontal position at unstretched arc length s [m].
  double z(double s) const;        ///< Height at s [m].
  double tension(double s) const;  ///< T(s) [N].
  double sag() const { return -z(0.5 * length); }
  double maxTension() const { return tension(0.0); }
};

/// One simulation of a reference case: how far from the reference and what it cost.
struct Result
{
  std::string scenario;
  std::string method;
  int segments = 0;
  int iterations = 0;
  int substeps = 0;
  double over_relaxation = 1.0;  ///< pbd's SOR factor [-]
  double time_step = 0.0;        ///< [s]
  double shape_error = 0.0;      ///< Relative error of the case's shape measure (sag, period, ...) [-].
  double tension_error = 0.0;    ///< Relative error of the case's tension measure [-]; NaN when none.
  double cost = 0.0;             ///< CPU per simulated second [us/s].
  int solver_iterations = -1;    ///< direct: the most Newton iterations any sub-step took; else -1.
  bool failed = false;           ///< The simulation reported a failure (blow-up), ended non-finite, or (statics)
                                 ///< was not at rest at the end.
  std::string label;             ///< "auto" for the automatic choice, else empty.
};

/// The cases, with their reference values (docs/references.md rows).
struct Case
{
  std::string name;
  std::string reference;  ///< The row of docs/references.md.
  /// Runs the case with `params` (the method, resolution and effort; the case sets the physics). Throws
  /// std::invalid_argument, naming the case, for parameters the Tether refuses.
  std::function<Result(TetherParams params)> run;
  /// Parameters of the case at resolution `segments` (the case's physics; method and effort default).
  std::function<TetherParams(int segments)> base;
};

/// All cases: catenary_inextensible, catenary_ea100, large_strain, axial_drag, taut_string,
/// hanging_chain, paper_experiment.
const std::vector<Case>& cases();
/// The case called `name`; throws std::out_of_range.
const Case& findCase(const std::string& name);

/// One point of the stability map: a cable pulled by a vehicle at `speed` for 3 s with the given step and
/// stiffness. Bounded = no failure reported, finite, strain below 1. Throws std::invalid_argument for
/// parameters or a speed the Tether refuses (a vehicle beyond Tether::kMaxCoordinate).
struct StabilityPoint
{
  std::string method;
  double time_step = 0.0;      ///< [s]
  double stiffness = 0.0;      ///< EA [N]
  double speed = 0.0;          ///< [m/s]
  double critical_step = 0.0;  ///< dL / sqrt(EA / mu) [s]
  bool bounded = false;
  double max_strain = 0.0;  ///< [-]
};
StabilityPoint stability(SolverType method, double time_step, double stiffness, double speed,
                         double over_relaxation = 1.0);

/// Upward zero crossings of a sampled signal, linearly interpolated [s]: a period from a free oscillation.
struct CrossingCounter
{
  double last_t = std::numeric_limits<double>::quiet_NaN(), last_v = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> crossings;
  void add(double t, double v)
  {
    if (last_v < 0.0 && v >= 0.0)
    {
      crossings.push_back(last_t + (t - last_t) * (-last_v) / (v - last_v));
    }
    last_t = t, last_v = v;
  }
  /// Mean period between the first and last crossing [s]; NaN with fewer than two.
  double period() const
  {
    return crossings.size() < 2 ? std::numeric_limits<double>::quiet_NaN()
                                : (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  }
};

/// CPU time of the process [s].
double cpuSeconds();

}  // namespace rov_tether::study
