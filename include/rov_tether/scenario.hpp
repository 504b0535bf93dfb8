#pragma once

#include <string>
#include <vector>

#include "rov_tether/tether.hpp"
#include "rov_tether/tether_params.hpp"

namespace rov_tether
{

/// A vehicle waypoint: time [s] and attachment position [m].
struct Waypoint
{
  double time;
  Position position;
};

/**
 * An offline run: parameters, spool, vehicle path, duration and output rate.
 *
 * YAML form (z up):
 *   params: {iterations: 5, drag: 0.9}   # any model parameter; missing ones take defaults
 *   spool: [x, y, z]                    # [m]
 *   vehicle: [[t, x, y, z], ...]        # [s, m]; followed piecewise-linearly; omit for a free end
 *   duration: 20.0                      # [s]
 *   output_rate: 10.0                   # rows per simulated second
 */
struct Scenario
{
  std::string description;
  TetherParams params;
  Position spool = Position::Zero();
  std::vector<Waypoint> vehicle;  ///< Empty: the tether hangs from its spool with a free end.
  double duration = 0.0;
  double output_rate = 10.0;

  /// Vehicle position at time t [s]: piecewise-linear, held before the first and after the last
  /// waypoint; at two waypoints with the same time the later one wins from that time on (a jump).
  Position vehicleAt(double t) const;
};

/**
 * Feeds a scenario's vehicle path into a simulation as a pose stream would: samples every 10 ms, a
 * little ahead of the simulation, so the simulation interpolates between them.
 */
class PathDriver
{
 public:
  explicit PathDriver(const Scenario& scenario) : scenario_(scenario) {}
  /// A simulation set up for the scenario: spool, parameters, vehicle at its t = 0 position.
  Tether makeSimulation() const;
  /// Feeds the path up to t (plus one sample interval) and advances the simulation to t [s].
  void advanceTo(Tether& sim, double t);
  /// Interval between fed samples [s].
  static constexpr double kSampleInterval = 0.01;

 private:
  const Scenario& scenario_;
  std::uint64_t fed_samples_ = 0;  ///< Samples fed so far; sample k is at k * kSampleInterval.
};

/// Parses scenario YAML text. Returns "" on success, otherwise a message naming the bad field.
std::string parseScenario(const std::string& yaml_text, Scenario* scenario);
/// Reads and parses a scenario file. Returns "" on success, otherwise a message naming the bad field.
std::string loadScenario(const std::string& path, Scenario* scenario);
/// Applies a flat YAML map of parameters (as in config/default.yaml) on top of `params` and validates
/// the result. Returns "" on success, otherwise every problem found.
std::string parseParams(const std::string& yaml_text, TetherParams* params);
/// Reads a parameter file such as config/default.yaml; as parseParams.
std::string loadParamsFile(const std::string& path, TetherParams* params);
/// Applies "name=value" (value in YAML syntax) to `params`. Returns "" on success.
std::string applyAssignment(const std::string& assignment, TetherParams* params);

/// What a scenario run produced.
struct RunSummary
{
  std::uint64_t steps = 0;
  double cpu_seconds = 0.0;  ///< Time spent in the simulation (output excluded) [s].
  std::size_t state_rows = 0;
  std::size_t shape_rows = 0;
  double deployed_start = 0.0;       ///< [m]
  double deployed_end = 0.0;         ///< [m]
  double deployed_max = 0.0;         ///< [m]
  double max_tension = 0.0;          ///< Largest segment tension at any output time [N].
  double max_tension_vehicle = 0.0;  ///< Largest tension at the vehicle at any output time [N].
  double max_strain = 0.0;           ///< Largest geometric strain at any output time [-].
  std::uint64_t jumps = 0;           ///< Vehicle jumps handled.
};

/// Runs `scenario` and writes out_dir/state.csv and out_dir/shape.csv (created together at the end, so
/// a failed run leaves no partial file). Returns "" on success, otherwise the error.
std::string runScenario(const Scenario& scenario, const std::string& out_dir, RunSummary* summary);

/// The CSV headers, part of the documented format.
extern const char* const kStateCsvHeader;
extern const char* const kShapeCsvHeader;

}  // namespace rov_tether
