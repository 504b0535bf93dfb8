// makeObstacle: the primitives from the core, meshes from the rov_tether_mesh module (module.hpp), loaded
// the first time a mesh is asked for.
#include "rov_tether/geometry/make_obstacle.hpp"

#include <string>

#include "rov_tether/geometry/module.hpp"

namespace rov_tether
{

std::unique_ptr<Obstacle> makeObstacle(const ObstacleSpec& spec, Status* status)
{
  if (spec.type != ShapeType::Mesh)
  {
    return makePrimitive(spec, status);
  }
  // The module's entry point (mesh_obstacle.cpp): a mesh obstacle, or null with the reason in `status`.
  using MakeMesh = Obstacle* (*)(const ObstacleSpec* spec, Status* status);
  std::string error;
  const auto make =
      reinterpret_cast<MakeMesh>(moduleFunction("librov_tether_mesh.so", "rov_tether_make_mesh_obstacle", &error));
  if (make == nullptr)
  {
    if (status != nullptr)
    {
      *status = Status::error("obstacle '" + spec.name + "': mesh obstacles need the rov_tether_mesh module: " + error);
    }
    return nullptr;
  }
  return std::unique_ptr<Obstacle>(make(&spec, status));
}

}  // namespace rov_tether
