#include "rov_tether/make_obstacle.hpp"

namespace rov_tether
{

std::unique_ptr<Obstacle> makeObstacle(const ObstacleSpec& spec, Status* status)
{
  // Meshes: to come with mesh_obstacle.cpp (assimp + FCL); makePrimitive refuses them with a clear error.
  return makePrimitive(spec, status);
}

}  // namespace rov_tether
