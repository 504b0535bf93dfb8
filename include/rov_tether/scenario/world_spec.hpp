#pragma once
// The one description of a world, whatever it was read from (a scenario file, tether_node's parameters), and
// the one builder of a World from it, for the node and the offline runner alike. Part of rov_tether_scenario:
// no YAML and no ROS here (the readers fill it: scenario_yaml.hpp, the node's loaders); meshes are built
// through rov_tether_geometry (makeObstacle).

#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario.hpp"
#include "rov_tether/spec/camera_spec.hpp"

namespace rov_tether
{

/**
 * A world as described: its tethers (each with its parameters, spool and vehicle path), the obstacles they
 * share, contact between tethers, and the cameras that look at them. A single-tether scenario is a list of
 * one tether called "tether"; so is a node without a `tethers` list.
 */
struct WorldSpec
{
  /// In World order. A tether's vehicle path is the runner's (empty: a free end, or the node, whose vehicle
  /// end follows its pose input).
  std::vector<ScenarioTether> tethers;
  /// Shared by every tether; a mesh `file` is a path the loader can open (the readers resolve it).
  std::vector<ObstacleSpec> obstacles;
  bool tether_contact = false;  ///< World::setContactBetweenTethers.
  /// Checked here with the tethers' and obstacles' names; built by the caller, which knows how they look at
  /// the world (the node's CameraSet on tf frames, the runner's DatasetWriter on the vehicle).
  std::vector<spec::CameraSpec> cameras;
  /// The dynamic vehicles are attached after buildWorld, by the caller (the node's, when each starts): it
  /// then mounts the spools that ride on them too (mountSpool). False (the runner): buildWorld does both.
  bool vehicles_attached_later = false;
};

/// The one rule for a tether's name, the node's and the runner's: 1-64 letters, digits, '_' or '-' (a
/// directory of the runner's output; the node's parameters and topics of a tether among several are under
/// ~<name>/, so the node also wants a ROS name: ros_layer::checkNodeTetherName).
bool isTetherName(const std::string& name);
/// What isTetherName allows, as said in messages.
extern const char* const kTetherNameRule;

/// Checks what the description's parts cannot check alone: each tether's name (isTetherName) and that it is
/// used once, and that no obstacle or camera takes a tether's name or another's of its kind. Returns "" or
/// the first problem, naming the entry ("tethers[1].name = 'a': used twice").
[[nodiscard]] std::string validateWorldSpec(const WorldSpec& spec);

/// Mounts tether i's spool (spec.tethers[i].spool_on) on its carrier in `world` (built from `spec`):
/// World::mountSpool. "" or the error, naming the entry ("tethers[1].spool.on = 'umbilical': ...").
[[nodiscard]] std::string mountSpool(const WorldSpec& spec, std::size_t i, World* world);

/// A scenario's world: its tetherList() (the one tether of params, spool and vehicle is called "tether"),
/// obstacles, tether_contact and cameras.
WorldSpec worldSpecOf(const Scenario& scenario);

/// One tether of a description as a simulation: at its spool, the vehicle end at its path's t = 0
/// position (or laid down from the spool without a path; a dynamic vehicle's at its start attachment point,
/// still kinematic: buildWorld attaches the body), at time 0.
Tether makeTether(const ScenarioTether& tether);

/**
 * Builds `spec` into `world` (empty; an error leaves it half built, to be thrown away): validateWorldSpec,
 * contact between tethers, every tether (makeTether, and its dynamic vehicle attached: attachDynamicVehicle,
 * which refuses a solver other than `direct`) in order, then every obstacle, each built once
 * (makeObstacle: a mesh file is read here and only here). What was built is in the World: its tethers
 * (World::tether) and obstacles (World::obstacle, with their specs and poses). Returns "" or the error,
 * naming the entry ("obstacles[0]: obstacle 'wreck': mesh file '...': cannot be read ...").
 * A spool that rides on another tether's vehicle (ScenarioTether::spool_on) starts at the outlet of that
 * vehicle's start pose and is mounted on it (mountSpool), unless spec.vehicles_attached_later.
 * A spool of its own (no vehicle or tf frame moves it) below its tether's seabed_z or inside a primitive obstacle
 * placed in the world is refused, naming both.
 * What is taken but must be said, a vehicle (a path's start, a dynamic vehicle's) out of its cable's reach, is
 * appended to `warnings` (not null), named as an error is ("tether far: vehicle: ..." among several); nothing is
 * printed: the runner prints them with its warnings, the node logs them, Python raises them with warnings.warn.
 */
[[nodiscard]] std::string buildWorld(const WorldSpec& spec, World* world, std::vector<std::string>* warnings);

}  // namespace rov_tether
