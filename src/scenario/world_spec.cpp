#include "rov_tether/scenario/world_spec.hpp"

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <memory>
#include <sstream>
#include <string>

#include "rov_tether/geometry/make_obstacle.hpp"
#include "rov_tether/scenario/vehicle_driver.hpp"

namespace rov_tether
{

const char* const kTetherNameRule = "1-64 letters, digits, '_' or '-'";

bool isTetherName(const std::string& name)
{
  return !name.empty() && name.size() <= 64 &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") ==
             std::string::npos;
}

namespace
{

/// "" or `said(k, name, by_tether)` for the first of `items` whose name an earlier one (by_tether false) or a
/// tether took.
template <typename Item, typename Say>
std::string firstTakenName(const std::vector<Item>& items, const std::vector<std::string>& tethers, Say said)
{
  std::vector<std::string> seen;
  for (std::size_t k = 0; k < items.size(); ++k)
  {
    const std::string& name = items[k].name;
    if (std::count(tethers.begin(), tethers.end(), name) > 0)
    {
      return said(k, name, true);
    }
    if (std::count(seen.begin(), seen.end(), name) > 0)
    {
      return said(k, name, false);
    }
    seen.push_back(name);
  }
  return "";
}

}  // namespace

std::string validateWorldSpec(const WorldSpec& spec)
{
  std::vector<std::string> tethers;
  for (std::size_t i = 0; i < spec.tethers.size(); ++i)
  {
    const std::string& name = spec.tethers[i].name;
    const std::string who = "tethers[" + std::to_string(i) + "].name = '" + name + "'";
    if (!isTetherName(name))
    {
      return who + ": expected " + kTetherNameRule;
    }
    if (std::count(tethers.begin(), tethers.end(), name) > 0)
    {
      return who + ": used twice";
    }
    const std::string& on = spec.tethers[i].spool_on;
    if (!on.empty() && std::count(tethers.begin(), tethers.end(), on) == 0)
    {
      return "tethers[" + std::to_string(i) + "].spool.on = '" + on +
             "': " + (on == name ? "a tether cannot carry its own spool" : "no tether of that name listed before it");
    }
    tethers.push_back(name);
  }
  // The one tether of a world without a `tethers` list is called "tether" (a node's, a scenario's).
  const std::string hint =
      tethers.size() == 1 && tethers.front() == "tether" ? " (a world's one tether is called 'tether')" : "";
  const std::string error = firstTakenName(spec.obstacles, tethers,
                                           [&hint](std::size_t k, const std::string& name, bool by_tether)
                                           {
                                             return "obstacles[" + std::to_string(k) + "] '" + name +
                                                    "' name: taken by " +
                                                    (by_tether ? "a tether" + hint : "an earlier obstacle");
                                           });
  return error.empty() ? firstTakenName(spec.cameras, tethers,
                                        [](std::size_t k, const std::string& name, bool by_tether)
                                        {
                                          return "cameras[" + std::to_string(k) + "].name = '" + name +
                                                 "': " + (by_tether ? "already used by a tether" : "used twice");
                                        })
                       : error;
}

std::string mountSpool(const WorldSpec& spec, std::size_t i, World* world)
{
  const ScenarioTether& tether = spec.tethers[i];
  const Status mounted =
      world->mountSpool(world->find(tether.name), world->find(tether.spool_on), tether.spool_outlet_offset);
  return mounted.ok ? ""
                    : "tethers[" + std::to_string(i) + "].spool.on = '" + tether.spool_on + "': " + mounted.message;
}

WorldSpec worldSpecOf(const Scenario& scenario)
{
  WorldSpec spec;
  spec.tethers = scenario.tetherList();
  spec.obstacles = scenario.obstacles;
  spec.tether_contact = scenario.tether_contact;
  spec.cameras = scenario.cameras;
  return spec;
}

Tether makeTether(const ScenarioTether& tether)
{
  if (tether.dynamic)
  {
    return Tether(tether.params, tether.spool, startAttachment(*tether.dynamic), 0.0);
  }
  if (tether.vehicle.empty())
  {
    return Tether(tether.params, tether.spool, 0.0);
  }
  return Tether(tether.params, tether.spool, pathAt(tether.vehicle, 0.0), 0.0);
}

namespace
{

/// "" for a position every coordinate of which is within Tether::kMaxCoordinate; else "(x, y, z), beyond +-1e6 m".
std::string beyondReach(const Position& p)
{
  if (Tether::withinLimits(p))
  {
    return "";
  }
  std::ostringstream out;
  out << std::setprecision(10) << "(" << p.x() << ", " << p.y() << ", " << p.z() << "), beyond +-"
      << Tether::kMaxCoordinate << " m";
  return out.str();
}

/// "" or the first tether whose own spool (not one a vehicle or a tf frame moves) is below its seabed or inside an
/// obstacle (a primitive placed in the world: not one on a tf frame, nor a mesh).
std::string checkSpools(const WorldSpec& spec, const World& world)
{
  for (std::size_t i = 0; i < spec.tethers.size(); ++i)
  {
    const ScenarioTether& tether = spec.tethers[i];
    if (!tether.spool_on.empty() || tether.spool_moves)
    {
      continue;  // carried by a vehicle or a tf frame, which moves it
    }
    const std::string who = spec.tethers.size() == 1 ? "spool" : "tethers: " + tether.name + ": spool";
    const Position& at = tether.spool;
    char where[160];
    std::snprintf(where, sizeof where, "[%g, %g, %g] m", at.x(), at.y(), at.z());
    const double seabed = world.tether(i).params().seabed_z;
    if (at.z() < seabed)
    {
      // The seabed holds the cable above it: the first segment would be stretched from the spool up to it.
      char text[96];
      std::snprintf(text, sizeof text, " is below the seabed (seabed_z = %g m)", seabed);
      return who + " " + where + text;
    }
    for (std::size_t k = 0; k < world.obstacleCount(); ++k)
    {
      Push push;
      // An obstacle on a tf frame (the node's) is not yet where its position says; a mesh is a surface, whose
      // inside a point test does not see.
      const Obstacle& obstacle = world.obstacle(k);
      const bool placed = obstacle.spec().frame.empty() && obstacle.spec().type != ShapeType::Mesh;
      if (placed && obstacle.push(at, at, 0.0, &push))
      {
        // The cable would start inside a solid that pushes every particle out of it.
        return who + " " + where + " is inside obstacle '" + obstacle.name() + "'";
      }
    }
  }
  return "";
}

}  // namespace

std::string buildWorld(const WorldSpec& spec, World* world, std::vector<std::string>* warnings)
{
  const std::string invalid = validateWorldSpec(spec);
  if (!invalid.empty())
  {
    return invalid;
  }
  world->setContactBetweenTethers(spec.tether_contact);
  for (ScenarioTether tether : spec.tethers)
  {
    const std::string who = spec.tethers.size() == 1 ? "" : "tethers: " + tether.name + ": ";
    const std::size_t carrier = tether.spool_on.empty() ? World::npos : world->find(tether.spool_on);
    if (carrier != World::npos && spec.tethers[carrier].dynamic)
    {
      // The outlet where the carrier's body starts (validateWorldSpec: the carrier was listed, so built, before).
      const VehicleBody body = startBody(*spec.tethers[carrier].dynamic);
      tether.spool = body.position() + body.attitude() * tether.spool_outlet_offset;
      const std::string beyond = beyondReach(tether.spool);
      if (!beyond.empty())
      {
        return who + "spool: on " + tether.spool_on + ": its vehicle's start plus outlet_offset puts the spool at " +
               beyond;
      }
    }
    if (tether.dynamic)
    {
      // Each of start and attachment_offset is checked alone by the reader; their sum may still be out of reach.
      const std::string beyond = beyondReach(startAttachment(*tether.dynamic));
      if (!beyond.empty())
      {
        return who + "vehicle: start plus attachment_offset puts the attachment at " + beyond;
      }
    }
    const Status added = world->add(tether.name, std::make_unique<Tether>(makeTether(tether)));
    if (!added.ok)
    {
      return "tethers: " + added.message;
    }
    std::string warning;
    const std::string attached = attachDynamicVehicle(tether, &world->tether(world->size() - 1), &warning);
    if (!attached.empty())
    {
      return (spec.tethers.size() == 1 ? "" : "tethers: " + tether.name + ": ") + attached;
    }
    const std::string& out_of_reach = world->tether(world->size() - 1).lastOutOfReach();
    if (!tether.dynamic && !out_of_reach.empty())
    {
      warning = "vehicle: " + out_of_reach;  // its path's start, as attachDynamicVehicle says a dynamic vehicle's
    }
    if (!warning.empty())
    {
      warnings->push_back((spec.tethers.size() == 1 ? "" : "tether " + tether.name + ": ") + warning);
    }
  }
  for (std::size_t i = 0; i < spec.tethers.size() && !spec.vehicles_attached_later; ++i)
  {
    const std::string mounted = spec.tethers[i].spool_on.empty() ? "" : mountSpool(spec, i, world);
    if (!mounted.empty())
    {
      return mounted;
    }
  }
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  for (std::size_t k = 0; k < spec.obstacles.size(); ++k)
  {
    Status status;
    obstacles.push_back(makeObstacle(spec.obstacles[k], &status));
    if (!obstacles.back())
    {
      return "obstacles[" + std::to_string(k) + "]: " + status.message;
    }
  }
  const Status placed = world->setObstacles(std::move(obstacles));
  return placed.ok ? checkSpools(spec, *world) : "obstacles: " + placed.message;
}

}  // namespace rov_tether
