#pragma once
// A tether's `sections:` and `attachments:` (issue 22), read from its description (a scenario's `params:`, a
// node's namespace) by the one reader of its parameters (tether_reader.hpp).

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "rov_tether/core/cable_section.hpp"

namespace rov_tether::spec
{

/**
 * `sections:` a list of maps, each `length` [m] (left out on the last: it runs to the drum) and any per-metre
 * parameter of the tether as a number. Returns "" or every problem with its place ("<prefix>sections[2].length:
 * expected a number"); what the values mean is checked by TetherParams::validate.
 */
[[nodiscard]] std::string readSections(const YAML::Node& node, const std::string& prefix,
                                       std::vector<CableSection>* sections);

/**
 * `attachments:` a list of maps with `name`, `arc_length_from_vehicle` [m] (both required), `mass` [kg],
 * `net_buoyancy` [N, up positive], `added_mass` [kg], `drag_area` [m^2], `drag_coefficient` (0 by default, 1
 * for drag_coefficient). An unknown key is an error. Returns "" or every problem with its place.
 */
[[nodiscard]] std::string readAttachments(const YAML::Node& node, const std::string& prefix,
                                          std::vector<CableAttachment>* attachments);

}  // namespace rov_tether::spec
