#pragma once
// Reading scenarios and parameter files (YAML, through yaml-cpp). The model is scenario.hpp.

#include <string>
#include <vector>

#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether
{

/// Whether a scenario must give its `duration` (a run of the runner's), or may leave it out (a world stepped as far
/// as it is advanced: the Python API's description). Left out, Scenario::duration is 0 and nothing is checked against
/// it (duration x output_rate, a camera's frames over the run); each rate is still checked alone.
enum class ScenarioDuration
{
  kRequired,
  kOptional,
};

/// Parses scenario YAML text. Returns "" on success, otherwise a message naming the bad field. A mesh
/// obstacle's relative `file` stays relative (to the working directory).
[[nodiscard]] std::string parseScenario(const std::string& yaml_text, Scenario* scenario,
                                        ScenarioDuration duration = ScenarioDuration::kRequired);
/// Reads and parses a scenario file. Returns "" on success, otherwise a message naming the bad field. A mesh
/// obstacle's relative `file` is taken from the scenario file's directory.
[[nodiscard]] std::string loadScenario(const std::string& path, Scenario* scenario);
/// Applies a flat YAML map of parameters (as in config/default.yaml) on top of `params` and validates
/// the result. Returns "" on success, otherwise every problem found.
[[nodiscard]] std::string parseParams(const std::string& yaml_text, TetherParams* params);
/// Reads a parameter file such as config/default.yaml; as parseParams.
[[nodiscard]] std::string loadParamsFile(const std::string& path, TetherParams* params);
/// Applies "name=value" (value in YAML syntax) to `params`. Returns "" on success.
[[nodiscard]] std::string applyAssignment(const std::string& assignment, TetherParams* params);
/// Applies every "name=value" together, as one map of parameters, then validates once (so that their order does not
/// matter: `initial_deployed_length=25` with `cable_length=30` in either order); `params` changes only on success.
/// The name is a key as it is, never YAML text: a name that is not a parameter's is refused as unknown.
[[nodiscard]] std::string applyAssignments(const std::vector<std::string>& assignments, TetherParams* params);

}  // namespace rov_tether
