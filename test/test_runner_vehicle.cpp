// The runner's `vehicle:` block (issue 25, "Runner"): a dynamic vehicle read, refused, run and written to
// vehicle.csv. Each bound says where it comes from.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/scenario/vehicle_driver.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether::test
{
namespace
{

/// buildWorld's warnings (a vehicle out of its cable's reach), which the tests here that build a world do not check
/// (Runner.APathStartingOutOfTheTethersReachIsSaid does).
std::vector<std::string> world_warnings;

namespace fs = std::filesystem;

const std::string kBlueRov = std::string(ROV_TETHER_SOURCE_DIR) + "/config/vehicles/bluerov2_heavy.yaml";

std::string scenarioWith(const std::string& vehicle)
{
  return "duration: 1\nparams: {winch_mode: locked, initial_deployed_length: 5, cable_length: 5}\nspool: [0, 0, 0]\n"
         "vehicle: " +
         vehicle + "\n";
}

std::string outputDirectory(const std::string& name)
{
  const fs::path dir =
      fs::temp_directory_path() / ("rov_tether_test_vehicle_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir.string();
}

/// vehicle.csv (or any CSV with a header) as one map per row, column name to number.
std::vector<std::map<std::string, double>> csvRows(const fs::path& path)
{
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream names(line);
  for (std::string name; std::getline(names, name, ',');)
  {
    header.push_back(name);
  }
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line))
  {
    std::stringstream cells(line);
    std::map<std::string, double> row;
    std::string cell;
    for (std::size_t i = 0; i < header.size() && std::getline(cells, cell, ','); ++i)
    {
      row[header[i]] = std::stod(cell);
    }
    rows.push_back(row);
  }
  return rows;
}

// A dynamic block reads the vehicle file (and its controller: block), starts at the path's first point with
// heading 0, and a `controller:` block of its own replaces the file's gains.
TEST(VehicleBlock, ReadsADynamicVehicle)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(scenarioWith("{model: dynamic, params: " + kBlueRov +
                                       ", path: [[0, 5, 0, -1], [1, 6, 0, -1]], attachment_offset: [-0.2, 0, 0]}"),
                          &scenario),
            "");
  ASSERT_TRUE(scenario.dynamic.has_value());
  EXPECT_EQ(scenario.vehicle.size(), 2u);
  EXPECT_EQ(scenario.dynamic->start, Position(5, 0, -1));
  EXPECT_EQ(scenario.dynamic->start_yaw, 0.0);
  EXPECT_EQ(scenario.dynamic->attachment_offset, Eigen::Vector3d(-0.2, 0, 0));
  EXPECT_EQ(scenario.dynamic->params.mass, 13.5);
  EXPECT_NEAR(scenario.dynamic->controller.proportional[0], ControllerGains{}.proportional[0], 1e-9);
  EXPECT_TRUE(scenario.dynamic->wrench.empty());

  ASSERT_EQ(
      parseScenario(scenarioWith("{model: dynamic, params: " + kBlueRov +
                                 ", start: [4, 1, -2, 0.5], path: [[0, 5, 0, -1]], controller: {bandwidth: [2, 2, "
                                 "2, 2], level_bandwidth: 4}}"),
                    &scenario),
      "");
  EXPECT_EQ(scenario.dynamic->start, Position(4, 1, -2));
  EXPECT_EQ(scenario.dynamic->start_yaw, 0.5);
  EXPECT_NEAR(scenario.dynamic->controller.proportional[0], 19.86 * (4.0 + 1.6), 1e-9);  // m' (w^2 + 2 w 0.2 w)
  EXPECT_GT(scenario.dynamic->controller.level_proportional[0], 0.0);

  ASSERT_EQ(
      parseScenario(scenarioWith("{model: dynamic, params: " + kBlueRov +
                                 ", start: [5, 0, -1, 0], wrench: [[0, 10, 0, 0, 0, 0, 0], [2, 20, 0, 0, 0, 0, 1]]}"),
                    &scenario),
      "");
  ASSERT_EQ(scenario.dynamic->wrench.size(), 2u);
  EXPECT_TRUE(scenario.vehicle.empty());
  EXPECT_DOUBLE_EQ(wrenchAt(scenario.dynamic->wrench, 1.0)[0], 15.0);  // piecewise-linear
  EXPECT_DOUBLE_EQ(wrenchAt(scenario.dynamic->wrench, 5.0)[5], 1.0);   // held after the last row
}

// `model: kinematic` is today's list: the same path, no body; and no `vehicle` at all stays a free end.
TEST(VehicleBlock, KinematicBlockIsTheList)
{
  Scenario listed;
  Scenario blocked;
  ASSERT_EQ(parseScenario(scenarioWith("[[0, 5, 0, -1], [1, 6, 0, -1]]"), &listed), "");
  ASSERT_EQ(parseScenario(scenarioWith("{model: kinematic, path: [[0, 5, 0, -1], [1, 6, 0, -1]]}"), &blocked), "");
  EXPECT_FALSE(blocked.dynamic.has_value());
  ASSERT_EQ(blocked.vehicle.size(), listed.vehicle.size());
  for (std::size_t k = 0; k < listed.vehicle.size(); ++k)
  {
    EXPECT_EQ(blocked.vehicle[k].time, listed.vehicle[k].time);
    EXPECT_EQ(blocked.vehicle[k].position, listed.vehicle[k].position);
  }
}

// Bad blocks are refused naming the field (exit code 2 in the runner), and nothing is read.
TEST(VehicleBlock, BadBlocksAreRefusedNamingTheField)
{
  const std::string params = "params: " + kBlueRov + ", ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{model: flying, path: [[0, 5, 0, 0]]}", "vehicle.model: expected kinematic or dynamic (got 'flying')"},
      {"{path: [[0, 5, 0, 0]]}", "vehicle.model: expected kinematic or dynamic"},
      {"{model: dynamic, " + params + "path: [[0, 5, 0, 0]], wrench: [[0, 1, 0, 0, 0, 0, 0]]}",
       "vehicle: give either path (the controller's setpoints) or wrench (a thrust schedule, no controller), not both"},
      {"{model: dynamic, " + params + "start: [0, 0, 0, 0]}", "vehicle: give either path"},
      {"{model: dynamic, " + params + "path: [[0, 5, 0, 0]], speed: 3}", "vehicle: unknown field 'speed'"},
      {"{model: dynamic, path: [[0, 5, 0, 0]]}", "vehicle.params: missing"},
      {"{model: dynamic, " + params + "path: [[0, 5, .nan, 0]]}", "vehicle.path[0][2]: must be finite"},
      {"{model: dynamic, " + params + "start: [0, 0, 0, .inf], wrench: [[0, 1, 0, 0, 0, 0, 0]]}",
       "vehicle.start[3]: must be finite"},
      {"{model: dynamic, " + params + "start: [0, 0, 0, 0], wrench: [[0, 1, 0, 0, .nan, 0, 0]]}",
       "vehicle.wrench[0][4]: must be finite"},
      {"{model: dynamic, " + params + "start: [0, 0, 0, 0], wrench: [[0, 1, 0, 0]]}",
       "vehicle.wrench[0]: expected a list of 7 numbers"},
      {"{model: dynamic, " + params + "wrench: [[0, 1, 0, 0, 0, 0, 0]]}", "vehicle.start: missing"},
      {"{model: dynamic, " + params + "start: [0, 0, 0, 0], wrench: [[0, 1, 0, 0, 0, 0, 0]], controller: {}}",
       "vehicle.controller: no controller runs under a wrench schedule"},
      {"{model: dynamic, " + params + "path: [[0, 5, 0, 0]], controller: {gain: 1}}",
       "vehicle: controller: gain: no controller setting of that name"},
      {"{model: dynamic, params: {mass: 3}, path: [[0, 5, 0, 0]]}", "vehicle.params: displaced_volume: missing"},
      {"{model: dynamic, params: no_such_vehicle.yaml, path: [[0, 5, 0, 0]]}",
       "vehicle.params: no_such_vehicle.yaml: cannot be read"},
      {"{model: kinematic, " + params + "path: [[0, 5, 0, 0]]}", "vehicle.params: only with model: dynamic"},
      {"{model: kinematic}", "vehicle.path: missing"},
      {"3", "vehicle: expected a list of [t, x, y, z] waypoints or a map"},
  };
  for (const auto& [block, expected] : cases)
  {
    Scenario scenario;
    const std::string error = parseScenario(scenarioWith(block), &scenario);
    EXPECT_EQ(error.rfind(expected, 0), 0u) << block << "\n  gave: " << error;
    EXPECT_FALSE(scenario.dynamic.has_value()) << block;
  }
  Scenario scenario;
  EXPECT_EQ(parseScenario(scenarioWith("{model: dynamic, " + params +
                                       "path: [[0, 1, 0, 0]]}\ncameras: [{name: c, width: 64, height: 48, K: [50, 0, "
                                       "31.5, 0, 50, 23.5, 0, 0, 1]}]"),
                          &scenario)
                .rfind("cameras: not with a dynamic vehicle", 0),
            0u);
}

// Only `direct` couples a vehicle: another solver (in the file, or by --set after it) is refused when the world
// is built, naming the solver, as the runner's exit code 2.
TEST(VehicleBlock, OnlyTheDirectSolverCouplesAVehicle)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(scenarioWith("{model: dynamic, params: " + kBlueRov + ", path: [[0, 5, 0, 0]]}"), &scenario),
            "");
  ASSERT_EQ(applyAssignment("solver=xpbd", &scenario.params), "");
  World world;
  EXPECT_EQ(buildWorld(worldSpecOf(scenario), &world, &world_warnings),
            "vehicle: a dynamic vehicle is coupled only by the direct solver, and this tether's solver is xpbd (set "
            "params.solver: direct)");
}

// Each of a dynamic vehicle's start and attachment_offset (and a carried spool's outlet_offset) is checked alone by
// the reader, within +-1e6 m and the offsets' limit; their sum was not, and the tether's constructor threw past
// +-1e6 m: rov_tether_run aborted (exit 134, an uncaught exception). buildWorld refuses it, naming the sum.
TEST(VehicleBlock, AStartPlusAnOffsetBeyondReachIsRefusedNotThrown)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(scenarioWith("{model: dynamic, params: " + kBlueRov +
                                       ", start: [1000000, 0, 0, 0], attachment_offset: [0.5, 0, 0], "
                                       "path: [[0, 1000000, 0, 0]]}"),
                          &scenario),
            "");
  World world;
  std::string error;
  EXPECT_NO_THROW(error = buildWorld(worldSpecOf(scenario), &world, &world_warnings));
  EXPECT_EQ(error,
            "vehicle: start plus attachment_offset puts the attachment at (1000000.5, 0, 0), beyond +-1000000 m");
  Scenario carried;
  ASSERT_EQ(
      parseScenario("duration: 1\ntethers:\n"
                    "  - {name: u, spool: [999999, 0, 0], params: {initial_deployed_length: 1, cable_length: 5},\n"
                    "     vehicle: {model: dynamic, params: " +
                        kBlueRov +
                        ", start: [1000000, 0, 0, 0], wrench: [[0, 0, 0, 0, 0, 0, 0]]}}\n"
                        "  - {name: t, spool: {on: u, outlet_offset: [0.5, 0, 0]}, params: {cable_length: 5},\n"
                        "     vehicle: [[0, 999999, 0, 0]]}\n",
                    &carried),
      "");
  World carrier_world;
  EXPECT_NO_THROW(error = buildWorld(worldSpecOf(carried), &carrier_world, &world_warnings));
  EXPECT_EQ(error.rfind("tethers: t: spool: on u: its vehicle's start plus outlet_offset puts the spool at (", 0), 0u)
      << error;
}

// A vehicle floats in its tether's water, or is said not to. The BlueROV2 Heavy's file takes fresh water (1000
// kg/m^3: rho g V = 131.45 N, 0.98 N heavy); on a tether in sea water (the default 1025) it floats in other water
// than its cable. buildWorld says so among its warnings, with both densities and the buoyancy it would have in
// the tether's (134.74 N, 2.31 N light: rho g V with the tether's rho), and says nothing with the tether's water
// set alike. (Tether::attachVehicleBody's message, which the node logs as the runner does.) Seen failing with
// the check left out: no warning. The tether's water changed live after the attachment is said likewise
// (Tether::setParams' message, which Python's set_param warns; the node cannot change water_density live).
TEST(VehicleBlock, AVehicleInOtherWaterThanItsTetherIsSaid)
{
  const VehicleParams fresh;  // the BlueROV2 Heavy's defaults, the file's values
  ASSERT_EQ(fresh.water_density, 1000.0);
  const double volume = fresh.displaced_volume, g = fresh.gravity;
  for (const double tether_water : {1025.0, 1000.0})
  {
    SCOPED_TRACE(tether_water);
    Scenario scenario;
    ASSERT_EQ(parseScenario("duration: 1\nparams: {winch_mode: locked, initial_deployed_length: 5, cable_length: 5, "
                            "water_density: " +
                                std::to_string(tether_water) +
                                "}\nspool: [0, 0, 0]\nvehicle: {model: dynamic, params: " + kBlueRov +
                                ", start: [4, 0, 0, 0], wrench: [[0, 0, 0, 0, 0, 0, 0]]}\n",
                            &scenario),
              "");
    World world;
    std::vector<std::string> warnings;
    ASSERT_EQ(buildWorld(worldSpecOf(scenario), &world, &warnings), "");
    if (tether_water == fresh.water_density)
    {
      EXPECT_TRUE(warnings.empty()) << warnings.front();
      // The tether's water changed live, the vehicle attached: said as at the attachment (it was taken without a
      // word), and nothing when changed back.
      TetherParams salt = world.tether(0).params();
      salt.water_density = 1025.0;
      ASSERT_TRUE(world.tether(0).vehicleDynamic());
      const std::string before = world.tether(0).checkParams(salt).message;  // what Python warns before the change
      const Status changed = world.tether(0).setParams(salt);
      ASSERT_TRUE(changed.ok) << changed.message;
      EXPECT_EQ(changed.message.rfind("vehicle: its water_density 1000 kg/m^3 is not the tether's 1025 kg/m^3: ", 0),
                0u)
          << changed.message;
      EXPECT_EQ(before, changed.message);
      salt.water_density = fresh.water_density;
      EXPECT_EQ(world.tether(0).setParams(salt).message, "");
      continue;
    }
    ASSERT_EQ(warnings.size(), 1u);
    char expected[320];
    std::snprintf(expected, sizeof expected,
                  "vehicle: its water_density 1000 kg/m^3 is not the tether's 1025 kg/m^3: its buoyancy is %.4g N, "
                  "%.4g N heavy in water, where in the tether's water it would be %.4g N, %.4g N light",
                  1000.0 * g * volume, fresh.mass * g - 1000.0 * g * volume, 1025.0 * g * volume,
                  1025.0 * g * volume - fresh.mass * g);
    EXPECT_EQ(warnings.front().rfind(expected, 0), 0u) << warnings.front() << "\n" << expected;
  }
}

// A thrust schedule is the body-frame command, held piecewise-linearly over each step from the step's start
// (the row at t shows the last step, from t - dt), each axis held at its limit and reported: a surge ramp from 0
// to 200 N over 1 s gives wrenchAt(t - dt) below 113.7 N and exactly 113.7 N (bit 0 set) above; no controller,
// so nothing on the other axes. The vehicle floats free on a slack tether (5 m paid out to a vehicle 2 m away).
// Seen failing with the schedule taken at the step's end.
TEST(VehicleRunner, AWrenchScheduleIsHeldPiecewiseLinearlyAndSaturated)
{
  Scenario scenario;
  ASSERT_EQ(
      parseScenario("duration: 1\noutput_rate: 20\nparams: {initial_deployed_length: 5, cable_length: 5}\n"
                    "spool: [0, 0, 0]\nvehicle: {model: dynamic, params: " +
                        kBlueRov + ", start: [2, 0, 0, 0], wrench: [[0, 0, 0, 0, 0, 0, 0], [1, 200, 0, 0, 0, 0, 0]]}\n",
                    &scenario),
      "");
  const std::string dir = outputDirectory("wrench");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  const auto rows = csvRows(fs::path(dir) / "vehicle.csv");
  ASSERT_EQ(rows.size(), 21u);
  EXPECT_EQ(summary.vehicle_rows, 21u);
  const double dt = scenario.params.time_step;
  for (std::size_t k = 1; k < rows.size(); ++k)
  {
    const double t = rows[k].at("t");
    const double asked = 200.0 * (t - dt);
    const double limit = 113.7;
    EXPECT_NEAR(rows[k].at("thrust_x"), std::min(asked, limit), 1e-3) << t;
    EXPECT_EQ(rows[k].at("saturated"), asked > limit ? 1.0 : 0.0) << t;
    EXPECT_EQ(rows[k].at("thrust_y"), 0.0);
    EXPECT_EQ(rows[k].at("thrust_n"), 0.0);
  }
  EXPECT_GT(rows.back().at("u"), 0.1) << "the thrust moved it forward";
  fs::remove_all(dir);
}

// The snag (issue 25): scenarios/pillar_wrap_dynamic.yaml, the pillar wrap with a dynamic BlueROV2 Heavy, with
// the winch slowed to 0.3 m/s (--set max_winch_speed=0.3) so that it cannot pay out as fast as the path goes
// round (1 m/s): the wrapped tether snags. Written at every step (output_rate 200). Physics: the tether's pull
// F on the vehicle is balanced by what the vehicle has, M a = T + D + g + F, so
// |F| <= |T|max + m_eff |a|max + |D|max + |W - B| with
//   |T|max = |(113.7, 113.7, 160.8)| = 227.3 N, the translational thrust limits together (in any direction);
//   m_eff = 32.18 kg, the largest mass with added mass (heave), times the largest acceleration the run shows
//     (finite differences of the world-frame velocity between steps);
//   |D|max the drag at the run's largest speed on each axis, X_u|u| + X_uu u^2 summed over the axes;
//   |W - B| = 0.88 N (13.5 kg in fresh water, 0.0134 m^3).
// Every row's pull (vehicle.csv) and the tension of the last segment (state.csv) stay within it, while the
// kinematic pillar wrap with the same winch (scenarios/pillar_wrap.yaml, a pose stream: no thrust limit, no
// inertia) stretches the snagged cable and pulls far more than that bound at its vehicle. Seen failing with
// the vehicle's thrust limits raised 1000-fold and a 10 rad/s controller (the bound kept at the real limits):
// that vehicle pulls 88 kN, shaking at 5590 m/s^2, and the kinematic comparison fails.
TEST(VehicleRunner, DynamicPillarWrapIsHeldByItsTetherNotPulledThrough)
{
  const std::string root(ROV_TETHER_SOURCE_DIR);
  Scenario dynamic;
  ASSERT_EQ(loadScenario(root + "/scenarios/pillar_wrap_dynamic.yaml", &dynamic), "");
  ASSERT_TRUE(dynamic.dynamic.has_value());
  ASSERT_EQ(applyAssignment("max_winch_speed=0.3", &dynamic.params), "");
  dynamic.output_rate = 1.0 / dynamic.params.time_step;
  const std::string dir = outputDirectory("pillar");
  RunSummary summary;
  ASSERT_EQ(runScenario(dynamic, dir, &summary), "");
  EXPECT_EQ(summary.recoveries, 0u);
  const auto rows = csvRows(fs::path(dir) / "vehicle.csv");
  const auto states = csvRows(fs::path(dir) / "state.csv");
  ASSERT_EQ(rows.size(), states.size());
  ASSERT_GT(rows.size(), 3000u);

  const VehicleParams& p = dynamic.dynamic->params;
  const double thrust = p.thrust_limit.head<3>().norm();
  const double mass = (p.mass + p.added_mass.head<3>().array()).maxCoeff();
  double acceleration = 0.0;
  Eigen::Vector3d speed = Eigen::Vector3d::Zero();  // largest |body velocity| per axis
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    const auto& r = rows[k];
    const Eigen::Quaterniond q(r.at("qw"), r.at("qx"), r.at("qy"), r.at("qz"));
    const Eigen::Vector3d body(r.at("u"), r.at("v"), r.at("w"));
    const Eigen::Vector3d world = q * body;
    if (k > 0)
    {
      acceleration = std::max(acceleration, (world - previous).norm() / (r.at("t") - rows[k - 1].at("t")));
    }
    previous = world;
    speed = speed.cwiseMax(body.cwiseAbs());
  }
  double drag = 0.0;
  for (int i = 0; i < 3; ++i)
  {
    drag += p.linear_damping[i] * speed[i] + p.quadratic_damping[i] * speed[i] * speed[i];
  }
  const double net_weight = std::abs(p.weight() - p.buoyancy());
  const double bound = thrust + mass * acceleration + drag + net_weight;
  double largest_pull = 0.0;
  double largest_tension = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    largest_pull = std::max(largest_pull, rows[k].at("tether_tension"));
    largest_tension = std::max(largest_tension, states[k].at("tension_vehicle"));
  }
  EXPECT_LE(largest_pull, bound);
  EXPECT_LE(largest_tension, bound);

  Scenario kinematic;
  ASSERT_EQ(loadScenario(root + "/scenarios/pillar_wrap.yaml", &kinematic), "");
  ASSERT_EQ(applyAssignment("max_winch_speed=0.3", &kinematic.params), "");
  RunSummary kinematic_summary;
  const std::string kinematic_dir = outputDirectory("pillar_kinematic");
  ASSERT_EQ(runScenario(kinematic, kinematic_dir, &kinematic_summary), "");
  EXPECT_GT(kinematic_summary.max_tension_vehicle, bound);
  std::printf(
      "[ measured ] pillar wrap: dynamic vehicle's largest pull %.4g N, last segment %.4g N; bound %.4g N "
      "(thrust %.4g, m_eff a %.4g x %.4g, drag %.4g); kinematic vehicle %.4g N\n",
      largest_pull, largest_tension, bound, thrust, mass, acceleration, drag, kinematic_summary.max_tension_vehicle);
  fs::remove_all(dir);
  fs::remove_all(kinematic_dir);
}

}  // namespace
}  // namespace rov_tether::test
