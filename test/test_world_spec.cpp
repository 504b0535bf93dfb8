// The one description of a world (WorldSpec) and its one builder (buildWorld): names checked in one place,
// each mesh file read once from a scenario file to the end of its run. (The node's path to the same World:
// test/ros/test_ros_layer.cpp, WorldSpec.NodeAndRunnerBuildTheSameWorld.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rov_tether/geometry/mesh_obstacle.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/scenario/world_spec.hpp"

namespace rov_tether::test
{
namespace
{

/// buildWorld's warnings (a vehicle out of its cable's reach), which the tests here that build a world do not check
/// (Runner.APathStartingOutOfTheTethersReachIsSaid does).
std::vector<std::string> world_warnings;

namespace fs = std::filesystem;

TEST(WorldSpec, TetherNamesFollowOneRule)
{
  // The runner's rule, now the node's too: a directory name of 1-64 letters, digits, '_' or '-'.
  for (const std::string& good : std::vector<std::string>{"a", "rov_1", "t-0", "7", std::string(64, 'x')})
  {
    EXPECT_TRUE(isTetherName(good)) << good;
  }
  for (const std::string& bad : std::vector<std::string>{"", "a/b", "a b", "ä", "../x", std::string(65, 'x')})
  {
    EXPECT_FALSE(isTetherName(bad)) << bad;
  }
}

TEST(WorldSpec, NamesAreCheckedAcrossTethersObstaclesAndCameras)
{
  WorldSpec spec;
  spec.tethers.resize(2);
  spec.tethers[0].name = "a";
  spec.tethers[1].name = "b";
  spec.tethers[1].spool = Position(1.0, 0.0, 0.0);
  ObstacleSpec pillar;
  pillar.name = "pillar";
  pillar.type = ShapeType::Sphere;
  pillar.radius = 1.0;
  pillar.position = Position(5.0, 0.0, -5.0);
  spec.obstacles = {pillar};
  spec.cameras.resize(1);
  spec.cameras[0].name = "front";
  EXPECT_EQ(validateWorldSpec(spec), "");

  const auto error = [](WorldSpec changed) { return validateWorldSpec(changed); };
  WorldSpec bad = spec;
  bad.tethers[1].name = "a";
  EXPECT_EQ(error(bad), "tethers[1].name = 'a': used twice");
  bad = spec;
  bad.tethers[0].name = "a/b";
  EXPECT_EQ(error(bad), "tethers[0].name = 'a/b': expected 1-64 letters, digits, '_' or '-'");
  bad = spec;
  bad.obstacles.push_back(pillar);
  EXPECT_EQ(error(bad), "obstacles[1] 'pillar' name: taken by an earlier obstacle");
  bad = spec;
  bad.obstacles[0].name = "b";
  EXPECT_EQ(error(bad), "obstacles[0] 'b' name: taken by a tether");
  bad = spec;
  bad.cameras.push_back(spec.cameras[0]);
  EXPECT_EQ(error(bad), "cameras[1].name = 'front': used twice");
  bad = spec;
  bad.cameras[0].name = "a";
  EXPECT_EQ(error(bad), "cameras[0].name = 'a': already used by a tether");
  bad = spec;
  bad.tethers.resize(1);
  bad.tethers[0].name = "tether";
  bad.obstacles[0].name = "tether";
  EXPECT_EQ(error(bad), "obstacles[0] 'tether' name: taken by a tether (a world's one tether is called 'tether')");
  // buildWorld checks the same before it builds anything.
  World world;
  bad = spec;
  bad.tethers[1].name = "a";
  EXPECT_EQ(buildWorld(bad, &world, &world_warnings), "tethers[1].name = 'a': used twice");
}

// Issue 21: the scenario path read each mesh to check it, threw it away and read it again to run. Now the
// description keeps the file's name and buildWorld reads it, once, whether the run starts from a file
// (rov_tether_run: load, build, run) or from runScenario alone.
TEST(WorldSpec, AMeshFileIsReadOnceFromScenarioToRun)
{
  const fs::path dir = fs::temp_directory_path() / ("rov_tether_world_spec_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string wreck = std::string(ROV_TETHER_SOURCE_DIR) + "/meshes/wreck.stl";
  {
    std::ofstream file(dir / "wreck.yaml");
    file << "spool: [0, 0, 0]\nduration: 0.2\noutput_rate: 10\n"
         << "obstacles:\n  - {name: wreck, type: mesh, file: '" << wreck << "', position: [40, 0, -5]}\n";
  }
  const std::size_t before = meshFilesRead();
  Scenario scenario;
  ASSERT_EQ(loadScenario((dir / "wreck.yaml").string(), &scenario), "");
  EXPECT_EQ(meshFilesRead(), before) << "reading the description opens no mesh file";
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, (dir / "out").string(), &summary), "");
  EXPECT_EQ(meshFilesRead(), before + 1) << "one mesh obstacle: its file read once, by buildWorld";

  // As rov_tether_run does it: the world built first (a mesh that cannot be read is a bad scenario), then run.
  World world;
  ASSERT_EQ(buildWorld(worldSpecOf(scenario), &world, &world_warnings), "");
  ASSERT_EQ(runScenario(scenario, world, (dir / "out2").string(), &summary), "");
  EXPECT_EQ(meshFilesRead(), before + 2);
  ASSERT_EQ(world.obstacleCount(), 1u);
  EXPECT_EQ(world.obstacle(0).name(), "wreck");

  // A file that is not there is found when the world is built, naming the obstacle and the file.
  scenario.obstacles[0].file = (dir / "missing.stl").string();
  World broken;
  const std::string error = buildWorld(worldSpecOf(scenario), &broken, &world_warnings);
  EXPECT_NE(error.find("obstacles[0]: obstacle 'wreck': mesh file '"), std::string::npos) << error;
  EXPECT_NE(error.find("cannot be read"), std::string::npos) << error;
  fs::remove_all(dir);
}

// A spool of its own (not carried by a vehicle) must be where a cable can start: the seabed holds the cable above
// seabed_z, so a spool below it stretched the first segment up to it (a helper's 1 m under: 1780 N and strain
// 9.5 from the start), and an obstacle pushes every particle out of it, so a spool inside a pillar pulled
// 125 kN. Both are refused naming the spool, where it is and what it is in; on the seabed, or outside the
// obstacle, it is built. Another tether's spool is named with its tether. A spool or an obstacle that a tf frame
// will move (the node's) is not checked where its position puts it.
TEST(WorldSpec, ASpoolBelowTheSeabedOrInsideAnObstacleIsRefused)
{
  WorldSpec spec;
  spec.tethers.resize(1);
  spec.tethers[0].name = "tether";
  spec.tethers[0].spool = Position(0.0, 0.0, -1.0);
  spec.tethers[0].params.seabed_z = -1.0;
  ObstacleSpec pillar;
  pillar.name = "pillar";
  pillar.type = ShapeType::Cylinder;
  pillar.radius = 0.3;
  pillar.length = 10.0;
  pillar.position = Position(0.5, 0.0, 0.0);
  spec.obstacles = {pillar};
  World on_the_seabed;
  EXPECT_EQ(buildWorld(spec, &on_the_seabed, &world_warnings), "");

  WorldSpec below = spec;
  below.tethers[0].params.seabed_z = 0.0;
  World world;
  EXPECT_EQ(buildWorld(below, &world, &world_warnings), "spool [0, 0, -1] m is below the seabed (seabed_z = 0 m)");

  WorldSpec inside = spec;
  inside.obstacles[0].position = Position(0.2, 0.0, 0.0);
  World pillared;
  EXPECT_EQ(buildWorld(inside, &pillared, &world_warnings), "spool [0, 0, -1] m is inside obstacle 'pillar'");
  // The node's spool on a tf frame, and its obstacle on one, are not where their positions say yet: not checked.
  WorldSpec moving = below;
  moving.tethers[0].spool_moves = true;
  World framed_spool;
  EXPECT_EQ(buildWorld(moving, &framed_spool, &world_warnings), "");
  WorldSpec framed = inside;
  framed.obstacles[0].frame = "ship";
  World framed_obstacle;
  EXPECT_EQ(buildWorld(framed, &framed_obstacle, &world_warnings), "");

  inside.tethers.push_back(spec.tethers[0]);
  inside.tethers[0].spool = Position(-3.0, 0.0, -1.0);
  inside.tethers[1].name = "b";
  World two;
  EXPECT_EQ(buildWorld(inside, &two, &world_warnings), "tethers: b: spool [0, 0, -1] m is inside obstacle 'pillar'");
}

}  // namespace
}  // namespace rov_tether::test
