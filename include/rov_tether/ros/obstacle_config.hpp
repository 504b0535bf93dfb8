#pragma once

#include <XmlRpcValue.h>

#include <string>
#include <vector>

#include "rov_tether/obstacle.hpp"

namespace rov_tether::ros_layer
{

/// What tether_node shares among all its tethers (the private namespace `~` only, never `~name/`).
struct WorldOptions
{
  std::vector<ObstacleSpec> obstacles;  ///< The list `obstacles` (README "Obstacles and topology").
  bool tether_contact = false;          ///< World::setContactBetweenTethers: tethers touch each other and themselves.
};

/// Reads `obstacles` (spec::readObstacles: names unique, none one of `tether_names`; tf frames allowed; a
/// mesh `file` kept as written) and `tether_contact` from `dict` (the private namespace as a map) on top of
/// `options`. Returns "" or every problem, each naming its entry and field; `options` is changed only on
/// success.
std::string loadWorldOptions(const XmlRpc::XmlRpcValue& dict, WorldOptions* options,
                             const std::vector<std::string>& tether_names = {});

/// A mesh file as a path for the loader: `package://pkg/rest` becomes pkg's directory + /rest,
/// `file:///path` /path; a plain absolute path stays. Returns "" for what cannot be resolved (an unknown
/// package, a relative path: relative to what?), with the reason in `error`.
std::string resolveMeshFile(const std::string& file, std::string* error);

/// The same file as an rviz mesh_resource URI: package:// and file:// stay, a path becomes file://path.
std::string meshResourceUri(const std::string& file);

}  // namespace rov_tether::ros_layer
