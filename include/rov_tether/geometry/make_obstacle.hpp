#pragma once
/**
 * Builds any obstacle from its spec: the primitives of obstacle.hpp, and triangle meshes read from STL,
 * OBJ or DAE (assimp) and queried through FCL (mesh_obstacle.hpp). Part of rov_tether_geometry, so the
 * physics core itself needs neither library.
 */

#include <memory>

#include "rov_tether/core/obstacle.hpp"

namespace rov_tether
{

/// The obstacle `spec` describes, or null with the reason in `status` (an invalid spec, a mesh file that
/// cannot be read or holds no triangle).
std::unique_ptr<Obstacle> makeObstacle(const ObstacleSpec& spec, Status* status);

}  // namespace rov_tether
