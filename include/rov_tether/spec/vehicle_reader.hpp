#pragma once
// The one reader of a vehicle's parameters (VehicleParams) from YAML: a vehicle file (config/vehicles/) or a
// map in a scenario, with the same fields and messages.

#include <yaml-cpp/yaml.h>

#include <string>

#include "rov_tether/core/vehicle_controller.hpp"
#include "rov_tether/core/vehicle_params.hpp"

namespace rov_tether::spec
{

/// Reads every field of VehicleParams (its field names: numbers, and lists of 3 or 6 numbers) from
/// `map`, and its optional `controller:` block (readControllerGains). A vehicle is described whole: a missing
/// field, an unknown or repeated key, a value that is no finite number and a set VehicleParams::validate()
/// refuses (a negative mass, ...) are each an error. Returns "" or every problem, each "<prefix>: <field>: ..."
/// (the prefix names the file), separated by "; "; `params` (and `gains`, when not null: the block's gains, or
/// without a block ControllerGains::design for this vehicle with the default ControllerDesign) are set only
/// on success. A `controller:` block is checked whether or not `gains` is asked for.
[[nodiscard]] std::string readVehicleParams(const YAML::Node& map, const std::string& prefix, VehicleParams* params,
                                            ControllerGains* gains = nullptr);

/// Reads a vehicle file with readVehicleParams, prefixed with its path; a file that cannot be read or
/// parsed is "<path>: ..." too.
[[nodiscard]] std::string loadVehicleParamsFile(const std::string& path, VehicleParams* params,
                                                ControllerGains* gains = nullptr);

/// Reads a vehicle controller's block for `vehicle`: the design keys `bandwidth` (4 numbers: surge, sway,
/// heave [rad/s], yaw [rad/s]), `damping_ratio`, `integral_ratio`, `level_bandwidth` (ControllerDesign; each defaults
/// to ControllerDesign's) give ControllerGains::design(vehicle, ...); the gain keys `proportional`, `integral`,
/// `derivative`, `integral_limit` (4 numbers each) then replace the designed ones they name. An unknown or
/// repeated key, a non-finite number, a design the vehicle refuses and gains VehicleController::configure
/// refuses (negative, or an unstable loop) are errors, "<prefix>: controller: ...". `gains` set only on success.
[[nodiscard]] std::string readControllerGains(const YAML::Node& map, const std::string& prefix,
                                              const VehicleParams& vehicle, ControllerGains* gains);

}  // namespace rov_tether::spec
