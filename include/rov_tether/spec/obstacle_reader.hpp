#pragma once
// The one reader of a world's `obstacles` list, for the node (parameter server, converted to YAML) and the
// scenario runner (YAML files) alike: the same fields, checks and messages.

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"

namespace rov_tether::spec
{

/// What differs between the node's obstacles and a scenario's.
struct ObstacleReading
{
  /// Whether an obstacle may name a tf `frame` to move with (the node; a scenario has no tf).
  bool frames = false;
  /// A mesh `file` as written into what ObstacleSpec::file keeps; "" with the reason in *error when it is
  /// refused. Unset: kept as written.
  std::function<std::string(const std::string& file, std::string* error)> file;
};

/// Reads one entry of `obstacles` (a map with ObstacleSpec's fields: name, type, position, orientation,
/// radius, length, size, file, scale, friction, and frame where `reading.frames`) and validates it
/// (rov_tether::validate, and every coordinate and size within Tether::kMaxCoordinate). Returns "" or the
/// first problem, naming the entry (its index and name) and the field.
[[nodiscard]] std::string readObstacle(const YAML::Node& node, std::size_t index, const ObstacleReading& reading,
                                       ObstacleSpec* spec);

/// Reads the list `obstacles`: each entry as readObstacle. Returns "" or every problem found, separated by
/// "; "; `obstacles` is set only on success. Names (unique, none a tether's or a camera's) are the world's
/// to check: validateWorldSpec (world_spec.hpp), with the other parts of the description.
[[nodiscard]] std::string readObstacles(const YAML::Node& node, const ObstacleReading& reading,
                                        std::vector<ObstacleSpec>* obstacles);

}  // namespace rov_tether::spec
