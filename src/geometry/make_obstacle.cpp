#include "rov_tether/geometry/make_obstacle.hpp"

#include "rov_tether/geometry/mesh_obstacle.hpp"

namespace rov_tether
{

std::unique_ptr<Obstacle> makeObstacle(const ObstacleSpec& spec, Status* status)
{
  return spec.type == ShapeType::Mesh ? makeMeshObstacle(spec, status) : makePrimitive(spec, status);
}

}  // namespace rov_tether
