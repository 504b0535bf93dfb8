#pragma once
// Reading scenarios and parameter files (YAML, through yaml-cpp). The model is scenario.hpp.

#include <string>

#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether
{

/// Parses scenario YAML text. Returns "" on success, otherwise a message naming the bad field. A mesh
/// obstacle's relative `file` stays relative (to the working directory).
[[nodiscard]] std::string parseScenario(const std::string& yaml_text, Scenario* scenario);
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

}  // namespace rov_tether
