#pragma once
// The one reader of a vehicle's parameters (VehicleParams) from YAML: a vehicle file (config/vehicles/) or a
// map in a scenario, with the same fields and messages.

#include <yaml-cpp/yaml.h>

#include <string>

#include "rov_tether/core/vehicle_params.hpp"

namespace rov_tether::spec
{

/// Reads every field of VehicleParams (its field names: numbers, and lists of 3 or 6 numbers) from
/// `map`. A vehicle is described whole: a missing field, an unknown or repeated key, a value that is no
/// finite number and a set VehicleParams::validate() refuses (a negative mass, ...) are each an error.
/// Returns "" or every problem, each "<prefix>: <field>: ..." (the prefix names the file), separated by
/// "; "; `params` is set only on success.
[[nodiscard]] std::string readVehicleParams(const YAML::Node& map, const std::string& prefix, VehicleParams* params);

/// Reads a vehicle file with readVehicleParams, prefixed with its path; a file that cannot be read or
/// parsed is "<path>: ..." too.
[[nodiscard]] std::string loadVehicleParamsFile(const std::string& path, VehicleParams* params);

}  // namespace rov_tether::spec
