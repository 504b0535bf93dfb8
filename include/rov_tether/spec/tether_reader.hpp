#pragma once
// The one reader of a tether's model parameters, for the node (its namespace on the parameter server,
// converted to YAML) and the scenario runner (`params:` maps and parameter files) alike: the same value
// types, the core's one loader (applyParameters), the same messages.

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether::spec
{

/// Which keys of a map are read as model parameters.
enum class ParamKeys
{
  kEvery,      ///< Every key (a scenario's `params:`): one that names no parameter is an error.
  kModelOnly,  ///< Only the model's parameter names (a node's namespace, which holds its options too).
};

/// A parameter value as written: bool, integer, number, then string for a scalar (a quoted one is a
/// string), a list of numbers for a list. Returns "" or "<prefix><name>: expected ...".
[[nodiscard]] std::string readParamValue(const YAML::Node& node, const std::string& prefix, const std::string& name,
                                         ParamValue* value);

/// Applies the map's parameters on top of `params` (through applyParameters, which validates the
/// result). Returns "" or every problem, each "<prefix>" and what it names, separated by "; ";
/// `params` is changed only on success. Deprecation warnings go to `warnings` (prefixed).
[[nodiscard]] std::string readTetherParams(const YAML::Node& map, const std::string& prefix, ParamKeys keys,
                                           TetherParams* params, std::vector<std::string>* warnings);

/// A position [x, y, z] in m, each coordinate finite and within Tether::kMaxCoordinate; "" or a message
/// naming `field`. A missing node is "<field>: missing (expected [x, y, z] in m)".
[[nodiscard]] std::string readPosition(const YAML::Node& node, const std::string& field, Position* position);

}  // namespace rov_tether::spec
