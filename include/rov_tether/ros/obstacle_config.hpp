#pragma once

#include <XmlRpcValue.h>

#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether::ros_layer
{

/// What tether_node shares among all its tethers (the private namespace `~` only, never `~name/`).
struct WorldOptions
{
  std::vector<ObstacleSpec> obstacles;  ///< The list `obstacles` (docs/node.md "Obstacles and topology").
  bool tether_contact = false;          ///< World::setContactBetweenTethers: tethers touch each other and themselves.
};

/// A description with only names in it (the tethers', default otherwise), for validateWorldSpec while the
/// node's parameters are read part by part.
WorldSpec namesOnly(const std::vector<std::string>& tether_names, const std::vector<ObstacleSpec>& obstacles,
                    const std::vector<spec::CameraSpec>& cameras);

/// Reads `obstacles` (spec::readObstacles; tf frames allowed; a mesh `file` kept as written; names unique and
/// none one of `tether_names`: validateWorldSpec) and `tether_contact` from `dict` (the private namespace as a
/// map) on top of `options`. Returns "" or every problem, each naming its entry and field; `options` is changed only on
/// success.
std::string loadWorldOptions(const XmlRpc::XmlRpcValue& dict, WorldOptions* options,
                             const std::vector<std::string>& tether_names = {});

/// The node's world as described, for buildWorld (the runner's builder too): each tether of `names` ("tether"
/// for a node without a `tethers` list) with its parameters and spool position from `setups` (in the same
/// order; no vehicle path: the vehicle end follows the pose input), `options`' obstacles with each mesh file
/// resolved (resolveMeshFile) and tether_contact (its cameras: loadCameraConfigs). Returns "" or the
/// error (an obstacle whose file cannot be resolved, naming it); `spec` is set only on success.
std::string nodeWorldSpec(const std::vector<std::string>& names, const std::vector<TetherSetup>& setups,
                          const WorldOptions& options, WorldSpec* spec);

/// Whether `name` may name one of the node's tethers: isTetherName (the runner's rule too) and a ROS name (its
/// parameters and topics are under ~<name>/: a letter first, no '-'). Returns "" or why not, naming it.
std::string checkNodeTetherName(const std::string& name);

/// A mesh (or vehicle_params) file as a path for the loader: `package://pkg/rest` becomes pkg's directory + /rest,
/// `file:///path` /path; a plain absolute path stays. Returns "" for what cannot be resolved (an unknown
/// package, a relative path: relative to what?), with the reason in `error`.
std::string resolveMeshFile(const std::string& file, std::string* error);

/// The same file as an rviz mesh_resource URI: package:// and file:// stay, a path becomes file://path.
std::string meshResourceUri(const std::string& file);

}  // namespace rov_tether::ros_layer
