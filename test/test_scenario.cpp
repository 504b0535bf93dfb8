// Scenario files, parameter files and the rov_tether_run executable.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rov_tether/scenario/earlier_outputs.hpp"
#include "rov_tether/scenario/world_spec.hpp"
#include "rov_tether/study/study.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

/// buildWorld's warnings (a vehicle out of its cable's reach), which the tests here that build a world do not check
/// (Runner.APathStartingOutOfTheTethersReachIsSaid does).
std::vector<std::string> world_warnings;

namespace fs = std::filesystem;

const std::string kGood = R"(
params: {iterations: 5, bending: false, winch_mode: locked, drag: 0.95}
spool: [0, 0, -1]
vehicle:
  - [0, 1.5, 0, -1]
  - [2, 2.5, 0, -1]
duration: 3
output_rate: 4
)";

TEST(ScenarioFile, ParsesAGoodScenario)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  EXPECT_EQ(scenario.params.iterations, 5);
  EXPECT_FALSE(scenario.params.bending);
  EXPECT_EQ(scenario.params.winch_mode, WinchMode::kLocked);
  EXPECT_EQ(scenario.params.drag, 0.95);
  EXPECT_EQ(scenario.params.noise, TetherParams{}.noise);  // missing ones take defaults
  EXPECT_EQ(scenario.spool, Position(0, 0, -1));
  ASSERT_EQ(scenario.vehicle.size(), 2u);
  EXPECT_EQ(scenario.vehicleAt(1.0), Position(2.0, 0, -1));
  EXPECT_EQ(scenario.vehicleAt(9.0), Position(2.5, 0, -1));
  EXPECT_EQ(scenario.duration, 3.0);
  EXPECT_EQ(scenario.output_rate, 4.0);
}

// Sections and attachments are read from a tether's parameters, in the order written (from the vehicle end).
TEST(ScenarioFile, ParsesSectionsAndAttachments)
{
  const std::string yaml = R"(
params:
  cable_length: 20
  segment_length: 0.5
  sections:
    - {length: 5, weight_in_water: 2.0, axial_stiffness: 5e4}
    - {mass_per_length: 0.3}
  attachments:
    - {name: float, arc_length_from_vehicle: 10, mass: 0.5, net_buoyancy: 5, added_mass: 0.2, drag_area: 0.01}
spool: [0, 0, 0]
duration: 1
)";
  Scenario scenario;
  ASSERT_EQ(parseScenario(yaml, &scenario), "");
  const TetherParams& p = scenario.params;
  ASSERT_EQ(p.sections.size(), 2u);
  EXPECT_EQ(p.sections[0].length, 5.0);
  const std::vector<std::pair<std::string, double>> first = {{"weight_in_water", 2.0}, {"axial_stiffness", 5e4}};
  EXPECT_EQ(p.sections[0].properties, first);
  EXPECT_TRUE(std::isnan(p.sections[1].length));  // runs to the drum
  ASSERT_EQ(p.attachments.size(), 1u);
  const CableAttachment& a = p.attachments[0];
  EXPECT_EQ(a.name, "float");
  EXPECT_EQ(a.arc_length_from_vehicle, 10.0);
  EXPECT_EQ(a.mass, 0.5);
  EXPECT_EQ(a.net_buoyancy, 5.0);
  EXPECT_EQ(a.added_mass, 0.2);
  EXPECT_EQ(a.drag_area, 0.01);
  EXPECT_EQ(a.drag_coefficient, 1.0);  // not written: its default
}

struct BadScenario
{
  std::string yaml;
  std::string message;  ///< A part of the expected error.
};

TEST(ScenarioFile, BadScenariosNameTheField)
{
  const std::vector<BadScenario> cases = {
      {"[1, 2]", "expected a map"},
      {"spool: [0, 0, 0]\nduration: 1\nvehicel: []", "unknown field 'vehicel'"},
      {"duration: 1", "spool: missing"},
      {"spool: [0, 0]\nduration: 1", "spool: expected a list of 3 numbers"},
      {"spool: [0, x, 0]\nduration: 1", "spool[1]: expected a number"},
      {"spool: [0, .nan, 0]\nduration: 1", "spool[1]: must be finite"},
      {"spool: [0, 0, 0]", "duration: missing"},
      {"spool: [0, 0, 0]\nduration: -2", "duration = -2"},
      {"spool: [0, 0, 0]\nduration: 1\noutput_rate: 0", "output_rate = 0"},
      {"spool: [0, 0, 0]\nduration: 1e6\noutput_rate: 100", "more than 1e6 output times"},
      {"spool: [0, 0, 0]\nduration: 1\nvehicle: []", "vehicle: expected a non-empty list"},
      {"spool: [0, 0, 0]\nduration: 1\nvehicle: [[0, 1, 2]]", "vehicle[0]: expected a list of 4 numbers"},
      {"spool: [0, 0, 0]\nduration: 1\nvehicle: [[1, 0, 0, 0], [0.5, 1, 0, 0]]", "vehicle[1]: time"},
      {"spool: [0, 0, 0]\nduration: 1\nvehicle: [[-1, 0, 0, 0]]", "vehicle[0]: time"},
      {"params: {iterations: 0}\nspool: [0, 0, 0]\nduration: 1", "params.iterations = 0"},
      {"params: {itrations: 3}\nspool: [0, 0, 0]\nduration: 1", "params: unknown parameter 'itrations'"},
      {"params: {bending: maybe}\nspool: [0, 0, 0]\nduration: 1", "params.bending: wrong type"},
      {"params: {drag: [1]}\nspool: [0, 0, 0]\nduration: 1", "params.drag: wrong type (a list), expected a number"},
      {"params: {current: [1, 2]}\nspool: [0, 0, 0]\nduration: 1", "params.current: expected a list of 3 numbers"},
      {"params: {current: [1, a, 2]}\nspool: [0, 0, 0]\nduration: 1", "current: expected a list of numbers"},
      {"params: {segment_length: automatic}\nspool: [0, 0, 0]\nduration: 1", "params.segment_length: wrong type"},
      {"params: 3\nspool: [0, 0, 0]\nduration: 1", "params: expected a map"},
      // YAML reads nan as text: the message gives YAML's word for it.
      {"params: {drag: nan}\nspool: [0, 0, 0]\nduration: 1",
       "params.drag: wrong type (a string), expected a number (YAML writes NaN and infinity as .nan, .inf and -.inf)"},
      {"spool: [0, 0, 0\nduration: 1", "YAML error"},
      // A repeated key: yaml-cpp keeps both and a lookup takes the first (issue 26, item 13).
      {"spool: [0, 0, 0]\nduration: 1\nduration: 50", "duplicate key 'duration' (lines 2 and 3)"},
      {"params: {iterations: 3, iterations: 700}\nspool: [0, 0, 0]\nduration: 1", "duplicate key 'params.iterations'"},
      {"spool: [0, 0, 0]\nduration: 1\ntethers:\n  - {name: a, spool: [0, 0, 0], name: b}",
       "duplicate key 'tethers[0].name'"},
      // An alias inside its own anchor's node: a cycle every walk would follow for ever (fuzz_scenario's stack
      // overflow; corpus crash-alias-cycle).
      {"params: &p\n  noise: 0.001\n  more: *p\nspool: [0, 0, 0]\nduration: 1", "levels deep: an alias that refers"},
      // A cable's sections and attachments (issue 22): each problem named by its place.
      {"params: {sections: 3}\nspool: [0, 0, 0]\nduration: 1", "params.sections: expected a list of maps"},
      {"params: {sections: [{length: x}]}\nspool: [0, 0, 0]\nduration: 1",
       "params.sections[0].length: expected a number"},
      {"params: {sections: [{length: 3.33}, {}]}\nspool: [0, 0, 0]\nduration: 1",
       "section 1 of 2: length 3.33 m is not a whole number of segments of 0.1 m"},
      {"params: {sections: [{length: 5, drag: 0.9}, {}]}\nspool: [0, 0, 0]\nduration: 1",
       "section 1 of 2: 'drag' is not a property a section may set"},
      {"params: {sections: [{length: 5, weight_in_water: 1e9}, {}]}\nspool: [0, 0, 0]\nduration: 1",
       "section 1 of 2: weight_in_water = 1e+09"},
      {"params: {attachments: [{name: a, arc_length_from_vehicle: 2, colour: 1}]}\nspool: [0, 0, 0]\nduration: 1",
       "params.attachments[0].colour: unknown key"},
      {"params: {attachments: [{arc_length_from_vehicle: 2}]}\nspool: [0, 0, 0]\nduration: 1",
       "params.attachments[0].name: missing"},
      {"params: {attachments: [{name: a, arc_length_from_vehicle: 20}]}\nspool: [0, 0, 0]\nduration: 1",
       "params.attachments[0] 'a': arc_length_from_vehicle = 20 m"},
  };
  for (const auto& c : cases)
  {
    Scenario scenario;
    const std::string error = parseScenario(c.yaml, &scenario);
    EXPECT_NE(error.find(c.message), std::string::npos) << "yaml: " << c.yaml << "\nerror: " << error;
  }
  // A description whose duration may be left out (the Python API's) has none to check the rates against: 200 rows/s
  // and a 200 Hz camera are taken, duration 0, where the runner's file refuses them. Each rate alone is still checked,
  // and a duration given is checked with them.
  const std::string camera =
      "\nvehicle: [[0, 1, 0, 0], [10, 5, 0, 0]]\ncameras:\n  - {name: front, width: 64, height: "
      "48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1], rate: ";
  for (const std::string& taken :
       {std::string("spool: [0, 0, 0]\noutput_rate: 200"), "spool: [0, 0, 0]" + camera + "200}"})
  {
    Scenario scenario;
    EXPECT_EQ(parseScenario(taken, &scenario, ScenarioDuration::kOptional), "") << taken;
    EXPECT_EQ(scenario.duration, 0.0);
    EXPECT_NE(parseScenario(taken, &scenario).find("duration: missing"), std::string::npos);
  }
  for (const auto& c : std::vector<BadScenario>{
           {"spool: [0, 0, 0]\noutput_rate: 2e4", "output_rate = 20000"},
           {"spool: [0, 0, 0]" + camera + "2000}", "cameras[0].rate = 2000"},
           {"spool: [0, 0, 0]\nduration: 2e4\noutput_rate: 100", "duration x output_rate = 2000000"},
           {"spool: [0, 0, 0]\nduration: 1e4" + camera + "200}", "cameras[0].rate: duration x rate = 2000000"}})
  {
    Scenario scenario;
    const std::string error = parseScenario(c.yaml, &scenario, ScenarioDuration::kOptional);
    EXPECT_NE(error.find(c.message), std::string::npos) << "yaml: " << c.yaml << "\nerror: " << error;
  }
}

// Two ways a scenario's YAML was taken wrongly, found by a review: a second document after a '---' line was never
// read, its typo never reported (YAML::Load reads the first); and aliases of lists of aliases (ten levels of ten:
// 1e10 values in 700 bytes) made the duplicate-key walk, and any reader after it, run for hours. Both refused now,
// the second once 1e7 values are counted (10^9 here).
TEST(Scenario, ASecondDocumentAndAnAliasBombAreRefused)
{
  Scenario scenario;
  const std::string two =
      parseScenario("spool: [0, 0, 0]\nduration: 1\n---\nparams: {cable_length: 50, brake_tenson: 5}\n", &scenario);
  EXPECT_NE(two.find("2 YAML documents"), std::string::npos) << two;
  // An empty document (a '---' or '...' then '---' at the end) holds nothing left unread: taken.
  EXPECT_EQ(parseScenario("spool: [0, 0, 0]\nduration: 1\n---\n", &scenario), "");
  EXPECT_EQ(parseScenario("spool: [0, 0, 0]\nduration: 1\n...\n---\n", &scenario), "");
  std::string bomb = "l0: &l0 [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n";
  for (int level = 1; level <= 8; ++level)
  {
    const std::string below = "*l" + std::to_string(level - 1);
    bomb += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [" + below;
    for (int k = 1; k < 10; ++k)
    {
      bomb += ", " + below;
    }
    bomb += "]\n";
  }
  const auto start = std::chrono::steady_clock::now();
  const std::string refused = parseScenario(bomb + "spool: [0, 0, 0]\nduration: 1\n", &scenario);
  EXPECT_NE(refused.find("more than 10000000 values"), std::string::npos) << refused;
  std::printf("[ measured ] 1e9 values behind 8 levels of aliases refused in %.2f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  // A path of 100,000 waypoints (5 values each, a recorded dive at 10 Hz for almost 3 hours) is no bomb.
  std::string path = "spool: [0, 0, 0]\nduration: 1\nvehicle: [";
  for (int k = 0; k < 100000; ++k)
  {
    path += (k ? ", [" : "[") + std::to_string(0.01 * k) + ", 1.5, 0, 0]";
  }
  EXPECT_EQ(parseScenario(path + "]\n", &scenario), "");
}

// yaml-cpp 0.7 (Debian 12's) reads a ',' where no value can start (a scenario whose first line lost its '#', a
// flow list followed by a ',' at block level) as an endless run of empty documents at that place: loading it
// filled the memory (fuzz_scenario found it: a 600-byte scenario took 20 GB before the kernel killed the runner),
// and YAML::Load alone read it as an empty file. Refused now as a YAML error naming the line and column, by every
// reader (parseScenario, parseParams, checkYamlFile's). Seen failing on the old code by running out of memory
// (under `ulimit -v`: std::bad_alloc).
TEST(Scenario, AStrayCommaIsAYamlErrorNotAnEndlessRead)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
      {", 100 segments) is swept\nspool: [0, 0, 0]\nduration: 1\n", "line 1, column 1"},
      {",\n", "line 1, column 1"},
      {"[1, 2], 3\n", "line 1, column 7"}};
  for (const auto& [text, where] : cases)
  {
    Scenario scenario;
    const std::string error = parseScenario(text, &scenario);
    EXPECT_NE(error.find(where), std::string::npos) << text << "\n" << error;
    EXPECT_NE(error.find("where no value can start"), std::string::npos) << error;
    TetherParams params;
    EXPECT_NE(parseParams(text, &params).find("where no value can start"), std::string::npos) << text;
  }
  // Empty documents each start after the last: taken as before (ASecondDocumentAndAnAliasBombAreRefused).
  Scenario scenario;
  EXPECT_EQ(parseScenario("spool: [0, 0, 0]\nduration: 1\n---\n---\n", &scenario), "");
}

// A run's size was bounded only by its output times (1e6): 2,000 m of cable in 1 mm segments written 100 times a
// second for 10,000 s is 2e12 rows of shape.csv (a review saw 2.3 GB written in 20 s), and a 10 us step with 10,000
// sub-steps for 1e6 s is 1e15 sub-steps; both were taken. Refused now, naming the numbers, with the limits
// Scenario::kMaxShapeRows (1e9 rows) and kMaxSubSteps (1e10); an hour of the demo's dive is far within both.
TEST(ScenarioFile, ARunThatWouldFillADiskOrTakeDaysIsRefused)
{
  Scenario huge_output;
  ASSERT_EQ(parseScenario("params: {cable_length: 2000, segment_length: 0.001, initial_deployed_length: 2000}\n"
                          "spool: [0, 0, 0]\nduration: 10000\noutput_rate: 100\n",
                          &huge_output),
            "");
  const std::string rows = huge_output.checkRunSize();
  EXPECT_EQ(rows.rfind("shape.csv would hold up to 2e+12 rows (1000001 output times", 0), 0u) << rows;
  Scenario long_run;
  ASSERT_EQ(parseScenario(
                "params: {time_step: 1.0e-5, substeps: 10000}\nspool: [0, 0, 0]\nduration: 1000000\noutput_rate: 0.1\n",
                &long_run),
            "");
  const std::string steps = long_run.checkRunSize();
  EXPECT_EQ(steps.rfind("the run would take 1e+15 sub-steps", 0), 0u) << steps;
  // At the limit: 1,000 output times (99.9 s at 10 a second, and the start) of 999,001 particles (999 m in 1 mm
  // segments) is 999,001,000 rows, taken; of 1,000,001 particles 1,000,001,000, refused. A locked winch writes what
  // it laid out at the start, not the whole cable.
  Scenario edge;
  ASSERT_EQ(parseScenario("params: {cable_length: 999, segment_length: 0.001, initial_deployed_length: 2}\n"
                          "spool: [0, 0, 0]\nduration: 99.9\noutput_rate: 10\n",
                          &edge),
            "");
  EXPECT_EQ(edge.checkRunSize(), "");
  edge.params.cable_length = 1000.0;
  EXPECT_NE(edge.checkRunSize(), "");
  edge.params.winch_mode = WinchMode::kLocked;
  EXPECT_EQ(edge.checkRunSize(), "");
  Scenario hour;  // the demo's dive for an hour at 10 rows a second: 36,001 x 201 rows, 720,000 x 1 sub-steps
  ASSERT_EQ(loadScenario(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/spool_payout.yaml", &hour), "");
  hour.duration = 3600.0;
  EXPECT_EQ(hour.checkRunSize(), "");
}

// config/default.yaml holds every parameter at exactly the struct's default.
// pathAt finds the waypoint by bisection; against its definition, read off the path directly: held before
// the first waypoint and after the last, and between the last waypoint at or before t and the next, linear.
// 2000 waypoints with repeated times (a jump: the later one wins from that time on), probed at every
// waypoint's time, between them and beyond both ends: exactly the same positions (the same arithmetic).
// A NaN time gives the first waypoint, as before. wrenchAt shares the lookup.
TEST(ScenarioPath, BisectionFindsTheWaypointsTheDefinitionSays)
{
  std::vector<Waypoint> path;
  double time = 0.5;
  for (int k = 0; k < 2000; ++k)
  {
    time += k % 7 == 3 ? 0.0 : 0.01 * (1 + k % 5);  // every seventh a repeated time
    path.push_back({time, Position(std::sin(0.1 * k), std::cos(0.07 * k), -0.001 * k)});
  }
  const auto definition = [&](double t) -> Position
  {
    if (t < path.front().time)
    {
      return path.front().position;
    }
    std::size_t last = 0;  // the last waypoint at or before t
    for (std::size_t k = 0; k < path.size(); ++k)
    {
      last = path[k].time <= t ? k : last;
    }
    if (last + 1 == path.size())
    {
      return path.back().position;
    }
    const Waypoint& a = path[last];
    const Waypoint& b = path[last + 1];
    return a.position + (t - a.time) / (b.time - a.time) * (b.position - a.position);
  };
  std::vector<double> probes = {0.0, path.front().time - 1e-9, path.back().time + 1.0};
  for (std::size_t k = 0; k + 1 < path.size(); ++k)
  {
    probes.push_back(path[k].time);
    probes.push_back(0.5 * (path[k].time + path[k + 1].time));
  }
  for (const double t : probes)
  {
    ASSERT_EQ(pathAt(path, t), definition(t)) << "t = " << t;
  }
  EXPECT_EQ(pathAt(path, std::nan("")), path.front().position);
  EXPECT_EQ(pathAt({}, 1.0), Position::Zero());
}

TEST(ConfigFiles, DefaultYamlListsEveryParameterAtItsDefault)
{
  const std::string path = std::string(ROV_TETHER_SOURCE_DIR) + "/config/default.yaml";
  TetherParams loaded;
  loaded.iterations = 3;  // must be overwritten by the file
  ASSERT_EQ(loadParamsFile(path, &loaded), "");
  const TetherParams defaults;
  for (const auto& name : parameterNames())
  {
    EXPECT_TRUE(sameParamValue(getParameter(loaded, name), getParameter(defaults, name))) << name;
  }
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& name : parameterNames())
  {
    EXPECT_NE(text.find("\n" + name + ":"), std::string::npos) << name << " missing from default.yaml";
  }
}

// Every shipped configuration and scenario file loads (one loader for all of them).
TEST(ConfigFiles, EveryShippedFileLoads)
{
  int scenarios = 0;
  // scenarios/*.yaml and the camera dataset examples in scenarios/datasets/.
  for (const auto& entry : fs::recursive_directory_iterator(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios"))
  {
    if (!entry.is_regular_file())
    {
      continue;
    }
    Scenario scenario;
    EXPECT_EQ(loadScenario(entry.path().string(), &scenario), "") << entry.path();
    ++scenarios;
  }
  EXPECT_GE(scenarios, 6);
  // config/*.yaml also hold node options: they are loaded through the ROS loader in test_ros_layer.
}

TEST(ConfigFiles, AssignmentsOverrideParameters)
{
  TetherParams params;
  EXPECT_EQ(applyAssignment("iterations=3", &params), "");
  EXPECT_EQ(params.iterations, 3);
  EXPECT_EQ(applyAssignment("solver=pbd_sequential", &params), "");
  EXPECT_EQ(params.solver, SolverType::kPbdSequential);
  EXPECT_NE(applyAssignment("iterations", &params).find("name=value"), std::string::npos);
  EXPECT_NE(applyAssignment("drag=2", &params).find("drag = 2"), std::string::npos);
  EXPECT_EQ(params.drag, 0.9);  // a refused assignment changes nothing
}

// --set values were applied and validated one at a time: initial_deployed_length=25 before cable_length=30 was
// refused (25 > the 10 m cable), after it taken. And the name was pasted into YAML text: "drag: 0.5 #=0.7" set
// drag to 0.5 with its value and its own name hidden behind a comment. Now the assignments are one map, validated
// once, and a name is a key as it is.
TEST(ConfigFiles, AssignmentsApplyTogetherAndANameIsNeverYaml)
{
  for (const auto& order : {std::vector<std::string>{"initial_deployed_length=25", "cable_length=30"},
                            std::vector<std::string>{"cable_length=30", "initial_deployed_length=25"}})
  {
    TetherParams params;
    EXPECT_EQ(applyAssignments(order, &params), "") << order.front();
    EXPECT_EQ(params.initial_deployed_length, 25.0);
    EXPECT_EQ(params.cable_length, 30.0);
  }
  TetherParams params;
  const std::string hidden = applyAssignments({"drag: 0.5 #=0.7"}, &params);
  EXPECT_NE(hidden.find("unknown parameter 'drag: 0.5 #'"), std::string::npos) << hidden;
  EXPECT_NE(applyAssignments({"{drag: 0.5}=1"}, &params).find("unknown parameter"), std::string::npos);
  EXPECT_NE(applyAssignments({" =1"}, &params).find("expected name=value"), std::string::npos);  // no name
  EXPECT_EQ(params.drag, 0.9);
  // Refused whole: one bad value keeps the good one out too.
  EXPECT_NE(applyAssignments({"noise=0.001", "drag=7"}, &params).find("drag = 7"), std::string::npos);
  EXPECT_EQ(params.noise, TetherParams().noise);
  EXPECT_NE(applyAssignments({"noise=0.001", "noise=0.002"}, &params).find("'noise' given twice"), std::string::npos);
  EXPECT_EQ(applyAssignments({" noise\t= 0.001"}, &params), "");  // the spaces round a name dropped, as YAML's
  EXPECT_EQ(params.noise, 0.001);
  EXPECT_EQ(applyAssignments({"current=[0.3, 0, 0]"}, &params), "");  // a list value, in YAML syntax
  EXPECT_EQ(params.current[0], 0.3);
}

std::string temporaryDirectory(const std::string& name)
{
  const fs::path dir = fs::temp_directory_path() / ("rov_tether_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir.string();
}

int runRunner(const std::string& arguments)
{
  const int status = std::system((std::string(ROV_TETHER_RUNNER) + " " + arguments + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// runRunner with its standard error kept in the file `err`.
int runRunnerKeepingStderr(const std::string& arguments, const std::string& err)
{
  const int status = std::system((std::string(ROV_TETHER_RUNNER) + " " + arguments + " >/dev/null 2> " + err).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> readLines(const fs::path& path)
{
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
  {
    lines.push_back(line);
  }
  return lines;
}

/// topology.csv's rows as fields, header first.
std::vector<std::vector<std::string>> csvRows(const fs::path& path)
{
  std::vector<std::vector<std::string>> rows;
  for (const std::string& line : readLines(path))
  {
    std::vector<std::string> fields(1);
    for (const char c : line)
    {
      if (c == ',')
      {
        fields.emplace_back();
      }
      else
      {
        fields.back().push_back(c);
      }
    }
    rows.push_back(fields);
  }
  return rows;
}

// The summary states what ran: `segment_length: auto` as the length it chose (chords of 1 cm on a 2 m
// radius allow sqrt(8 x 2 x 0.01) = 0.4 m, and 40 m is 100 of them), not the 0.1 m default it replaced.
TEST(Runner, SummaryShowsWhatAutoChose)
{
  const std::string dir = temporaryDirectory("auto");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << "params: {cable_length: 40.0, segment_length: auto, shape_tolerance: 0.01, "
                                  "min_bend_radius: 2.0, initial_deployed_length: 10.0}\n"
                                  "spool: [0, 0, 0]\nduration: 0.1\n";
  const std::string out = dir + "_summary.txt";
  const std::string command =
      std::string(ROV_TETHER_RUNNER) + " " + scenario_path.string() + " --out " + dir + " > " + out + " 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::string text;
  for (const std::string& line : readLines(out))
  {
    text += line + "\n";
  }
  EXPECT_NE(text.find("segment 0.4 m"), std::string::npos) << text;
  // What ran: 10 m deployed in segments of 0.4 m is 25 segments, 26 particles at t = 0.
  int particles = 0;
  for (const std::string& line : readLines(fs::path(dir) / "shape.csv"))
  {
    particles += line.rfind("0.000000,", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(particles, 26);
  fs::remove(scenario_path);
  fs::remove(out);
  fs::remove_all(dir);
}

// The runner's start-up (issue 24: docs/benchmarks.md): FCL and assimp (meshes) and OpenCV (cameras) are
// modules it loads only for a scenario that asks for them (geometry/module.hpp). The loader's own record
// (glibc's LD_DEBUG=files, on stderr) says which libraries a run initialised: a plain scenario none of
// them; one with a mesh obstacle and a camera both, and the run writes the camera's frames through the
// module. Fails if the runner links either again, or if a module cannot be found from the build's lib.
TEST(Runner, LoadsTheMeshAndCameraModulesOnlyWhenAScenarioAsks)
{
  const std::string dir = temporaryDirectory("modules");
  const fs::path plain = fs::path(dir + "_plain.yaml");
  const fs::path full = fs::path(dir + "_full.yaml");
  std::ofstream(plain) << kGood;
  std::ofstream(full)
      << kGood << "obstacles:\n  - {name: wreck, type: mesh, file: '" << ROV_TETHER_SOURCE_DIR
      << "/meshes/wreck.stl', position: [40, 0, -5]}\n"
      << "cameras:\n  - {name: front, position: [0.5, 0, 0], orientation: [0, 0, 0], rate: 2, width: 64, height: 48, "
         "K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]}\n";
  auto loaded = [&](const fs::path& scenario, const std::string& out)
  {
    const std::string log = out + "_ld.txt";
    const std::string command = "LD_DEBUG=files " + std::string(ROV_TETHER_RUNNER) + " " + scenario.string() +
                                " --out " + out + " >/dev/null 2> " + log;
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::string text;
    for (const std::string& line : readLines(log))
    {
      text += line + "\n";
    }
    fs::remove(log);
    return text;
  };
  const std::string plain_log = loaded(plain, dir + "_a");
  ASSERT_NE(plain_log.find("calling init: "), std::string::npos) << "no loader record: " << plain_log;
  for (const char* library : {"libfcl", "libassimp", "libopencv_core", "librov_tether_mesh", "librov_tether_camera"})
  {
    EXPECT_EQ(plain_log.find(library), std::string::npos) << library << " loaded for a plain scenario";
  }
  const std::string full_log = loaded(full, dir + "_b");
  for (const char* library : {"libfcl", "libassimp", "libopencv_core", "librov_tether_mesh", "librov_tether_camera"})
  {
    EXPECT_NE(full_log.find(library), std::string::npos) << library << " not loaded for a mesh and a camera";
  }
  EXPECT_TRUE(fs::exists(fs::path(dir + "_b") / "cameras" / "front" / "index.csv"));
  EXPECT_TRUE(fs::exists(fs::path(dir + "_b") / "topology.csv"));
  for (const fs::path& p : {plain, full})
  {
    fs::remove(p);
  }
  fs::remove_all(dir + "_a");
  fs::remove_all(dir + "_b");
}

TEST(Runner, WritesStateAndShapeCsv)
{
  const std::string dir = temporaryDirectory("good");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << kGood;
  ASSERT_EQ(runRunner(scenario_path.string() + " --out " + dir), 0);

  const auto state = readLines(fs::path(dir) / "state.csv");
  ASSERT_EQ(state.size(), 1u + 13u);  // header + t = 0, 0.25, ..., 3
  EXPECT_EQ(state[0], kStateCsvHeader);
  EXPECT_EQ(state[1].rfind("0.000000,2.000000,", 0), 0u) << state[1];
  EXPECT_EQ(state.back().rfind("3.000000,2.000000,", 0), 0u) << state.back();  // locked winch

  const auto shape = readLines(fs::path(dir) / "shape.csv");
  ASSERT_EQ(shape.size(), 1u + 13u * 21u);  // 2 m in 20 segments: 21 particles per output time
  EXPECT_EQ(shape[0], kShapeCsvHeader);
  EXPECT_EQ(shape[1].rfind("0.000000,0,0.000000,0.000000,-1.000000,", 0), 0u) << shape[1];
  EXPECT_EQ(shape[21].back(), ',') << "the last particle has no segment, so no tension";
  EXPECT_EQ(shape[21].rfind("0.000000,20,1.500000,0.000000,-1.000000", 0), 0u) << shape[21];
  // Without obstacles, tethers or tether_contact, exactly the two files (no topology.csv, no directories).
  std::set<std::string> written;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
  {
    written.insert(fs::relative(entry.path(), dir).string());
  }
  EXPECT_EQ(written, (std::set<std::string>{"state.csv", "shape.csv"}));
  fs::remove_all(dir);
  fs::remove(scenario_path);
}

// The run simulates its whole duration, not only up to its last output time. kGood at time_step 0.005 s (the
// default) for 3.1 s at 4 rows per second: rows at 0, 0.25, ..., 3 as before, and then the 0.1 s after the last row:
// 3.1 / 0.005 = 620 steps (it stopped at 600, the world at t = 3). At 0.01 s, no whole output period, there is the
// one row at t = 0 and 0.01 / 0.005 = 2 steps, which the summary says ("simulated 0.01 s in 0 steps" before: the
// run stepped up to t = 0 only).
TEST(Runner, SimulatesTheWholeDurationPastTheLastOutputTime)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.duration = 3.1;
  const std::string dir = temporaryDirectory("whole_duration");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  EXPECT_EQ(summary.steps, 620u);
  EXPECT_NEAR(summary.simulated, 3.1, 1e-9);
  EXPECT_EQ(readLines(fs::path(dir) / "state.csv").size(), 1u + 13u);  // header + t = 0, 0.25, ..., 3
  fs::remove_all(dir);

  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::string text = kGood;
  text.replace(text.find("duration: 3"), std::string("duration: 3").size(), "duration: 0.01");
  std::ofstream(scenario_path) << text;
  const std::string out = dir + "_summary.txt";
  ASSERT_EQ(std::system((std::string(ROV_TETHER_RUNNER) + " " + scenario_path.string() + " --out " + dir + " > " + out +
                         " 2>&1")
                            .c_str()),
            0);
  std::string printed;
  for (const std::string& line : readLines(out))
  {
    printed += line + "\n";
  }
  EXPECT_NE(printed.find("simulated       0.01 s in 2 steps"), std::string::npos) << printed;
  EXPECT_EQ(readLines(fs::path(dir) / "state.csv").size(), 2u);  // header + t = 0
  fs::remove(scenario_path);
  fs::remove(out);
  fs::remove_all(dir);
}

// The summary's maxima cover every step the run simulates, the tail past the last output time too (1.05 s at one
// row a second: rows at 0 and 1 s, then 10 steps of 5 ms no row holds). A locked 10 m cable (EA 1e5 N, weightless,
// no noise) whose vehicle pulls it from 10 m at 0.01 m/s: quasi-static, its tension is the elastic EA (d - L) / L,
// rising to its most at the end, 105 N at 1.05 s (the last row's 100 N is 5% short); the bound, 1%, is well above
// the drag the moving cable feels (mu gamma v L / 2 ~ 0.03 N) and below the 5% the tail adds. A speed winch paying
// out at 0.5 m/s from 2 m (drive limit 1 m/s^2) has out L0 + v t - v^2 / (2 a) once at speed: 2.4 m at 1.05 s (the
// last row's 2.375 m is 0.025 m short), bound one step's pay-out, v h = 2.5 mm. The maxima were taken at the rows
// alone.
TEST(Runner, TheSummarysMaximaCoverEveryStepTheTailPastTheLastRowToo)
{
  const std::string pulled = R"(
params: {noise: 0, bending: false, winch_mode: locked, cable_length: 10, initial_deployed_length: 10}
spool: [0, 0, 0]
vehicle:
  - [0, 10, 0, 0]
  - [2, 10.02, 0, 0]
duration: 1.05
output_rate: 1
)";
  Scenario scenario;
  ASSERT_EQ(parseScenario(pulled, &scenario), "");
  const std::string dir = temporaryDirectory("tail_maxima");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  ASSERT_NEAR(summary.simulated, 1.05, 1e-9);
  ASSERT_EQ(summary.state_rows, 2u);  // t = 0 and 1 s: the tail is in no row
  const double ea = scenario.params.axial_stiffness;
  const double length = scenario.params.cable_length;
  const double at_end = ea * (scenario.vehicleAt(1.05).norm() - length) / length;
  std::printf(
      "[ measured ] pulled to 1.05 s: max tension %.4f N at %.3f s, at the vehicle %.4f N (elastic %.4f N; "
      "the last row's %.4f N)\n",
      summary.max_tension, summary.max_tension_time, summary.max_tension_vehicle, at_end,
      ea * (scenario.vehicleAt(1.0).norm() - length) / length);
  EXPECT_NEAR(summary.max_tension, at_end, 0.01 * at_end);
  EXPECT_NEAR(summary.max_tension_vehicle, at_end, 0.01 * at_end);
  EXPECT_NEAR(summary.max_tension_time, 1.05, 1e-9);
  EXPECT_NEAR(summary.max_strain, (scenario.vehicleAt(1.05).norm() - length) / length, 0.01 * at_end / ea);

  std::string paying = pulled;
  paying.replace(paying.find("winch_mode: locked, cable_length: 10, initial_deployed_length: 10"),
                 std::string("winch_mode: locked, cable_length: 10, initial_deployed_length: 10").size(),
                 "winch_mode: speed, winch_speed: 0.5, max_winch_acceleration: 1, initial_deployed_length: 2");
  paying.replace(paying.find("  - [0, 10, 0, 0]\n  - [2, 10.02, 0, 0]"),
                 std::string("  - [0, 10, 0, 0]\n  - [2, 10.02, 0, 0]").size(), "  - [0, 1.5, 0, 0]");
  ASSERT_EQ(parseScenario(paying, &scenario), "");
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  const double v = 0.5, a = 1.0, h = scenario.params.time_step;
  const double deployed = 2.0 + v * 1.05 - v * v / (2.0 * a);
  std::printf(
      "[ measured ] paying out to 1.05 s: max deployed %.4f m, at the end %.4f m (L0 + v t - v^2 / 2a "
      "%.4f m)\n",
      summary.deployed_max, summary.deployed_end, deployed);
  EXPECT_NEAR(summary.deployed_max, deployed, v * h);

  // A peak between two rows: the same locked cable pulled out 0.02 m by 0.5 s and let back by 1 s (rows at 0 and
  // 1 s, both with the cable at its length: 0 N). Quasi-static as above, the peak is the elastic EA 0.02 / L =
  // 200 N at 0.5 s (the path's turn), within 1% (the drag at 0.04 m/s, ~0.1 N, is far less) and within a step of
  // its time; the rows, and the run's last state, hold none of it.
  std::string there_and_back = pulled;
  there_and_back.replace(there_and_back.find("  - [2, 10.02, 0, 0]\nduration: 1.05"),
                         std::string("  - [2, 10.02, 0, 0]\nduration: 1.05").size(),
                         "  - [0.5, 10.02, 0, 0]\n  - [1, 10, 0, 0]\nduration: 1");
  ASSERT_EQ(parseScenario(there_and_back, &scenario), "");
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  ASSERT_EQ(summary.state_rows, 2u);
  const double peak = ea * 0.02 / length;
  std::printf("[ measured ] out and back by 1 s: max tension %.4f N at %.3f s (elastic %.4f N at 0.5 s)\n",
              summary.max_tension, summary.max_tension_time, peak);
  EXPECT_NEAR(summary.max_tension, peak, 0.01 * peak);
  EXPECT_NEAR(summary.max_tension_time, 0.5, scenario.params.time_step + 1e-9);
  fs::remove_all(dir);
}

// A parameter file (config/*.yaml, --params) that gives a key twice is refused whole, naming the key: either
// value could be the one meant (issue 26, item 13).
TEST(ConfigFiles, ARepeatedKeyIsRefusedNamingIt)
{
  TetherParams params;
  const std::string error = parseParams("iterations: 3\ndrag: 0.9\niterations: 700\n", &params);
  EXPECT_NE(error.find("duplicate key 'iterations' (lines 1 and 3)"), std::string::npos) << error;
  EXPECT_EQ(params.iterations, TetherParams{}.iterations);  // nothing applied
  EXPECT_EQ(params.drag, TetherParams{}.drag);
}

TEST(Runner, BadScenarioFailsAndWritesNothing)
{
  const std::string dir = temporaryDirectory("bad");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << "params: {drag: 3}\nspool: [0, 0, 0]\nduration: 1\n";
  EXPECT_EQ(runRunner(scenario_path.string() + " --out " + dir), 2);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "state.csv"));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "shape.csv"));
  EXPECT_EQ(runRunner("/nonexistent.yaml --out " + dir), 2);
  EXPECT_EQ(runRunner(scenario_path.string()), 2);  // no --out
  EXPECT_EQ(
      runRunner(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/catenary.yaml --out " + dir + " --set iterations=-3"),
      2);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "state.csv"));
  std::ofstream(scenario_path) << "spool: [0, 0, 0]\nduration: 1\nduration: 50\n";  // a repeated key
  EXPECT_EQ(runRunner(scenario_path.string() + " --out " + dir), 2);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "state.csv"));
  fs::remove(scenario_path);
}

// A path that was not validated (built in code, not read from a file) whose vehicle sample the simulation
// refuses: PathDriver stops there and says which sample, and the run returns that refusal and writes nothing,
// not the rows it had up to then (issue 21: a refused Status is never dropped). The path goes non-finite
// after t = 2 s (a NaN waypoint at 2.5 s: interpolated, every sample from 2.00 s on is NaN).
TEST(Runner, ARefusedVehicleSampleStopsTheRunAndWritesNothing)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.vehicle.push_back({2.5, Position(std::nan(""), 0.0, -1.0)});

  PathDriver driver(scenario);
  Tether sim = driver.makeSimulation();
  const Status status = driver.advanceTo(sim, 3.0);
  EXPECT_FALSE(status.ok);
  EXPECT_NE(status.message.find("vehicle path at t = 2.00"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("finite"), std::string::npos) << status.message;
  EXPECT_LT(sim.time(), 2.0);  // not advanced past the refused sample

  const std::string dir = temporaryDirectory("refused_sample");
  RunSummary summary;
  const std::string error = runScenario(scenario, dir, &summary);
  EXPECT_NE(error.find("vehicle path at t = 2.00"), std::string::npos) << error;
  std::set<std::string> written;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
  {
    written.insert(fs::relative(entry.path(), dir).string());
  }
  EXPECT_EQ(written, std::set<std::string>{});  // no state.csv, shape.csv, nor their partial files
  fs::remove_all(dir);
}

// A run writes into a directory that may hold an earlier run's outputs, and replaces only the files it writes
// (state.csv, shape.csv of kGood here). What it leaves of the earlier run is named in a warning, so that no one
// reads a mixed directory as one run's: a topology.csv and the state.csv of a tether it names (a/), and a
// camera directory of a camera it does not have. Its own camera's directory (forward/, whose frame 7 is past the
// frames 0 to 3 a camera at 1 Hz renders over kGood's 3 s) is replaced whole, and not named (its frames past this
// run's were, when the frames were written in place); nor is a run's temporary (.forward.partial). A target that
// is a directory fails before the run, and leaves no partial file.
TEST(Runner, AnEarlierRunsOutputsLeftInTheDirectoryAreNamed)
{
  const fs::path dir = temporaryDirectory("earlier");
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  ScenarioCamera forward;
  forward.name = "forward";
  forward.rate = 1.0;
  scenario.cameras.push_back(forward);
  ASSERT_EQ(scenario.cameraFrames(forward), 4u);
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "cameras" / "forward");
  fs::create_directories(dir / "cameras" / "aft");
  fs::create_directories(dir / "cameras" / ".forward.partial");  // a run's temporary, not an output
  for (const fs::path& file :
       {dir / "state.csv", dir / "a" / "state.csv", dir / "notes.txt", dir / "cameras" / "forward" / "index.csv",
        dir / "cameras" / "forward" / "mask_000003.png", dir / "cameras" / "forward" / "mask_000007.png",
        dir / "cameras" / "forward" / "depth_000007.png", dir / "cameras" / "forward" / "depth_preview_000007.png",
        dir / "cameras" / "aft" / "mask_000000.png", dir / "cameras" / ".forward.partial" / "mask_000000.png"})
  {
    std::ofstream(file) << "earlier\n";
  }
  std::ofstream(dir / "topology.csv") << kTopologyCsvHeader << "\n0.000000,a,b,linking_number,0\n";
  // forward's directory is this run's camera's, replaced whole (its frames past this run's 4 with it).
  const std::vector<std::string> expected = {"a/state.csv", "topology.csv",
                                             "cameras/aft/ (1 file: a camera this scenario does not have)"};
  EXPECT_EQ(earlierOutputs(scenario, dir, {dir / "state.csv", dir / "shape.csv"}), expected);
  EXPECT_TRUE(earlierOutputs(scenario, dir / "none", {}).empty());

  scenario.cameras.clear();
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs.size(), 4u);  // forward's directory is now of a camera it does not have
  const std::vector<std::string> warnings = runWarnings(scenario, summary, kDefaultMaxTensionWarning);
  ASSERT_FALSE(warnings.empty());  // kGood's cable is also over-tensioned, said after
  EXPECT_NE(warnings[0].find("earlier run's outputs that this run did not replace: a/state.csv; topology.csv; "
                             "cameras/aft/"),
            std::string::npos)
      << warnings[0];
  EXPECT_NE(readLines(dir / "state.csv").at(0), "earlier");  // its own, replaced

  fs::remove_all(dir);
  fs::create_directories(dir / "shape.csv");
  const std::string error = runScenario(scenario, dir.string(), &summary);
  EXPECT_EQ(error, "cannot write '" + (dir / "shape.csv").string() + "': it is a directory");
  std::set<std::string> left;
  for (const auto& entry : fs::directory_iterator(dir))
  {
    left.insert(entry.path().filename().string());
  }
  EXPECT_EQ(left, std::set<std::string>{"shape.csv"});  // no state.csv, no partial file
  fs::remove_all(dir);
}

// `--out results` beside other runs' folders (results/dive1/ of a single tether, results/seen/ with its cameras,
// results/pair/ of a tethers list with its topology.csv): those folders mix with nothing this run writes, so none of
// their files is named (every one was, file by file: "dive1/shape.csv; dive1/state.csv; ..."). What does mix is still
// named: a CSV left in a directory this run writes into (a tethers list's a/vehicle.csv of an earlier dynamic run);
// and, once out_dir holds an earlier world run's topology.csv that names c, c/'s tether files, which are that run's
// tether directory, while dive1/, which it does not name, is not.
TEST(Runner, OtherRunsFoldersInTheOutputDirectoryAreNotNamed)
{
  const fs::path dir = temporaryDirectory("other_runs");
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  for (const fs::path& sub : {dir / "dive1", dir / "seen" / "cameras" / "front", dir / "pair" / "a"})
  {
    fs::create_directories(sub);
  }
  for (const fs::path& file :
       {dir / "dive1" / "state.csv", dir / "dive1" / "shape.csv", dir / "seen" / "state.csv",
        dir / "seen" / "shape.csv", dir / "seen" / "cameras" / "front" / "mask_000000.png",
        dir / "pair" / "topology.csv", dir / "pair" / "a" / "state.csv", dir / "pair" / "a" / "shape.csv"})
  {
    std::ofstream(file) << "other run\n";
  }
  // A single tether writes state.csv and shape.csv in dir: the folders beside them are no output of its.
  EXPECT_EQ(earlierOutputs(scenario, dir, {dir / "state.csv", dir / "shape.csv"}), std::vector<std::string>{});
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, std::vector<std::string>{});
  for (const std::string& warning : runWarnings(scenario, summary, kDefaultMaxTensionWarning))
  {
    EXPECT_EQ(warning.find("earlier run"), std::string::npos) << warning;
  }
  // A tethers list (a, b) writes dir/a/, dir/b/ and dir/topology.csv: what is left in its own a/ is named, as is
  // the single tether's state.csv and shape.csv it leaves in dir.
  fs::create_directories(dir / "a");
  std::ofstream(dir / "a" / "vehicle.csv") << "earlier\n";
  const std::vector<fs::path> two = {dir / "a" / "state.csv", dir / "a" / "shape.csv", dir / "b" / "state.csv",
                                     dir / "b" / "shape.csv", dir / "topology.csv"};
  EXPECT_EQ(earlierOutputs(scenario, dir, two), (std::vector<std::string>{"a/vehicle.csv", "shape.csv", "state.csv"}));
  // An earlier world run's topology.csv in dir, of tethers a, b and c: c/ is its tether directory, dive1/ is not.
  // It names pair and seen as tethers too: a folder so named holds no tether's files only (a run's own
  // topology.csv, a camera directory), so it is another run's all the same, by the "no run of its own" guard.
  fs::create_directories(dir / "c");
  std::ofstream(dir / "c" / "state.csv") << "earlier\n";
  std::ofstream(dir / "topology.csv") << kTopologyCsvHeader << "\n0.000000,a,b,linking_number,0\n"
                                      << "0.000000,a,c,linking_number,0\n0.000000,b,c,linking_number,0\n"
                                      << "0.000000,pair,seen,linking_number,0\n";
  const std::vector<std::string> expected = {"a/vehicle.csv", "c/state.csv", "shape.csv", "state.csv"};
  EXPECT_EQ(earlierOutputs(scenario, dir, two), expected);
  fs::remove_all(dir);
}

/// The lines of `warnings` that say an earlier run's outputs were left (none, or the one).
std::vector<std::string> earlierRunWarnings(const std::vector<std::string>& warnings)
{
  std::vector<std::string> found;
  std::copy_if(warnings.begin(), warnings.end(), std::back_inserter(found),
               [](const std::string& w) { return w.find("earlier run's outputs") != std::string::npos; });
  return found;
}

/// `dir`/`name`/ as another run's folder: a single tether's state.csv and shape.csv.
void otherRunsFolder(const fs::path& dir, const std::string& name)
{
  fs::create_directories(dir / name);
  std::ofstream(dir / name / "state.csv") << kStateCsvHeader << "\n";
  std::ofstream(dir / name / "shape.csv") << kShapeCsvHeader << "\n";
}

/// A tethers list of hanging tethers 5 m apart, named `names` (no contact, no obstacle: only linking_number rows).
std::string hangingTethers(const std::vector<std::string>& names)
{
  std::string yaml = "duration: 0.5\noutput_rate: 10\ntethers:\n";
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    yaml += "  - {name: " + names[i] + ", params: {iterations: 3}, spool: [0, " + std::to_string(5 * i) + ", 0]}\n";
  }
  return yaml;
}

// A single tether with obstacles writes topology.csv beside its own state.csv and shape.csv, so a second run into
// the same `--out results` finds a topology.csv there, which took every folder of CSVs beside it (another run's
// results/dive1/) for an earlier world run's tether directory, and named its files as this run's earlier outputs.
// Only a tether its topology.csv names is taken: here `tether`, the single tether's own name, which with its
// state.csv in results is not a directory (results/tether/ is another run's too), and not dive1, though an obstacle
// of that name is in every row's `object` (a wrap's object is an obstacle, never a tether). Without the names both
// folders were named; with every row's object taken dive1/ is, without the state.csv's rule tether/ is.
TEST(Runner, ASingleTetherWithObstaclesTakesNoOtherRunsFolderForItsOwn)
{
  const fs::path dir = temporaryDirectory("single_obstacles");
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood + "obstacles:\n  - {name: dive1, type: cylinder, position: [0, 3, -1], radius: "
                                  "0.2, length: 2}\n",
                          &scenario),
            "");
  ASSERT_TRUE(scenario.usesWorld());
  otherRunsFolder(dir, "dive1");
  otherRunsFolder(dir, "tether");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, std::vector<std::string>{});  // nothing earlier yet
  // The premise: the topology.csv it left names tether (its wrap rows' tether) and dive1 (their object).
  const auto rows = csvRows(dir / "topology.csv");
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows[1].at(1), "tether");
  EXPECT_EQ(rows[1].at(2), "dive1");
  EXPECT_EQ(rows[1].at(3), "wrap_turns");
  ASSERT_TRUE(fs::is_regular_file(dir / "state.csv"));

  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, std::vector<std::string>{});
  EXPECT_EQ(earlierRunWarnings(runWarnings(scenario, summary, kDefaultMaxTensionWarning)), std::vector<std::string>{});
  fs::remove_all(dir);
}

// A tethers list (a, b) run again into its own `--out results`: the topology.csv it finds is the one it wrote before,
// which names a and b, not results/dive1/ beside them, another run's folder. That folder's files were named as this
// run's earlier outputs (any folder of CSVs beside an earlier topology.csv was taken for its tether directory).
TEST(Runner, AWorldRunAgainIntoItsFolderTakesNoOtherRunsFolderForItsOwn)
{
  const fs::path dir = temporaryDirectory("world_again");
  Scenario scenario;
  ASSERT_EQ(parseScenario(hangingTethers({"a", "b"}), &scenario), "");
  otherRunsFolder(dir, "dive1");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, std::vector<std::string>{});
  ASSERT_GE(csvRows(dir / "topology.csv").size(), 2u);  // the premise: an earlier topology.csv for the second run

  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, std::vector<std::string>{});
  EXPECT_EQ(earlierRunWarnings(runWarnings(scenario, summary, kDefaultMaxTensionWarning)), std::vector<std::string>{});
  EXPECT_EQ(readLines(dir / "dive1" / "state.csv"), std::vector<std::string>{kStateCsvHeader});  // left as it was
  fs::remove_all(dir);
}

// What the earlier topology.csv names is still taken: a tethers list (a, b, c) and then (a, b) into one folder leaves
// c/state.csv and c/shape.csv, the earlier run's, which are named (a reader would take c/ for this run's), while
// dive1/ beside them, another run's, is not. c, the last of three that touch nothing, is named in no row's `tether`,
// only as the object of its linking_number rows (a and c, b and c): named only when those objects are read. A
// topology.csv with no row (a tethers list of one that touched nothing) names no tether, and no folder is taken.
TEST(Runner, AnEarlierWorldRunsTetherDirectoryLeftBehindIsNamed)
{
  const fs::path dir = temporaryDirectory("world_left");
  Scenario three, two;
  ASSERT_EQ(parseScenario(hangingTethers({"a", "b", "c"}), &three), "");
  ASSERT_EQ(parseScenario(hangingTethers({"a", "b"}), &two), "");
  otherRunsFolder(dir, "dive1");
  RunSummary summary;
  ASSERT_EQ(runScenario(three, dir.string(), &summary), "");
  // The premise: c is in no row's `tether`, and the object of linking_number rows.
  const auto rows = csvRows(dir / "topology.csv");
  ASSERT_GE(rows.size(), 2u);
  std::set<std::string> tether_column, linked;
  for (std::size_t r = 1; r < rows.size(); ++r)
  {
    tether_column.insert(rows[r].at(1));
    EXPECT_EQ(rows[r].at(3), "linking_number");
    linked.insert(rows[r].at(2));
  }
  EXPECT_EQ(tether_column, (std::set<std::string>{"a", "b"}));
  EXPECT_EQ(linked, (std::set<std::string>{"b", "c"}));

  ASSERT_EQ(runScenario(two, dir.string(), &summary), "");
  EXPECT_EQ(summary.earlier_outputs, (std::vector<std::string>{"c/shape.csv", "c/state.csv"}));
  const std::vector<std::string> warnings = earlierRunWarnings(runWarnings(two, summary, kDefaultMaxTensionWarning));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("did not replace: c/shape.csv; c/state.csv. They are left"), std::string::npos)
      << warnings[0];

  // The same folder, its topology.csv of no row: nothing names c.
  std::ofstream(dir / "topology.csv") << kTopologyCsvHeader << "\n";
  EXPECT_EQ(earlierOutputs(two, dir,
                           {dir / "a" / "state.csv", dir / "a" / "shape.csv", dir / "b" / "state.csv",
                            dir / "b" / "shape.csv", dir / "topology.csv"}),
            std::vector<std::string>{});
  fs::remove_all(dir);
}

/// Makes `path` a directory with a file in it when the run reaches `time` [s]: something else writing where an
/// output goes after the run has opened its files (a directory there before the run is refused).
class DirectoryInTheWay : public RunObserver
{
 public:
  DirectoryInTheWay(fs::path path, double time) : path_(std::move(path)), time_(time) {}
  double nextTime() const override { return done_ ? std::numeric_limits<double>::infinity() : time_; }
  std::string observe(const Tether& /*sim*/) override
  {
    fs::create_directories(path_);
    std::ofstream(path_ / "notes.txt") << "someone else's\n";
    done_ = true;
    return "";
  }

 private:
  fs::path path_;
  double time_;
  bool done_ = false;
};

/// Every entry under `dir`, relative to it.
std::set<std::string> entriesUnder(const fs::path& dir)
{
  std::set<std::string> entries;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
  {
    entries.insert(fs::relative(entry.path(), dir).string());
  }
  return entries;
}

// A run writes each output under a partial name and moves them all into place at the end, and a move that failed
// half-way left some new files and some earlier ones, with an error naming only the file that failed: here
// b/shape.csv, a directory that came during the run, after a/state.csv, a/shape.csv and b/state.csv had been moved
// in over or beside the earlier a/ and topology.csv. All or nothing: the error names that file and says that no
// CSV output was replaced, and every CSV file is as it was (a/'s and topology.csv's earlier contents, no b/state.csv,
// where there was none; the directory in the way untouched; no partial or moved-aside file left). A file at a name an
// earlier output is moved aside to (.topology.csv.earlier, left by a run that stopped while it moved its outputs,
// maybe the only copy of an earlier file) is refused before the run, named, and kept; without it the run replaces
// every file and leaves no moved-aside one.
TEST(Runner, AMoveIntoPlaceThatFailsHalfWayReplacesNothing)
{
  const fs::path dir = temporaryDirectory("move_fails");
  Scenario scenario;
  ASSERT_EQ(parseScenario(hangingTethers({"a", "b"}), &scenario), "");
  fs::create_directories(dir / "a");
  const std::vector<fs::path> earlier = {dir / "a" / "state.csv", dir / "a" / "shape.csv", dir / "topology.csv"};
  for (const fs::path& file : earlier)
  {
    std::ofstream(file) << "earlier\n";
  }
  DirectoryInTheWay in_the_way(dir / "b" / "shape.csv", 0.2);
  RunSummary summary;
  EXPECT_EQ(runScenario(scenario, dir.string(), &summary, {&in_the_way}),
            "cannot move '" + (dir / "b" / "shape.csv").string() +
                "' into place: " + std::make_error_code(std::errc::is_a_directory).message() +
                ". No CSV output was replaced: every CSV file is as it was before this run");
  EXPECT_EQ(entriesUnder(dir), (std::set<std::string>{"a", "a/shape.csv", "a/state.csv", "b", "b/shape.csv",
                                                      "b/shape.csv/notes.txt", "topology.csv"}));
  for (const fs::path& file : earlier)
  {
    EXPECT_EQ(readLines(file), std::vector<std::string>{"earlier"}) << file;
  }
  EXPECT_EQ(readLines(dir / "b" / "shape.csv" / "notes.txt"), std::vector<std::string>{"someone else's"});

  fs::remove_all(dir / "b");
  std::ofstream(dir / ".topology.csv.earlier") << "the only copy\n";
  const std::string error = runScenario(scenario, dir.string(), &summary);
  EXPECT_EQ(error.rfind("cannot write '" + (dir / "topology.csv").string() + "': '" +
                            (dir / ".topology.csv.earlier").string() + "' is in the way",
                        0),
            0u)
      << error;
  // Either case, and what to do in each: a stopped run's copy may be the only one; a finished run's is older.
  EXPECT_NE(error.find("may be the only copy of the earlier one: put it back"), std::string::npos) << error;
  EXPECT_NE(error.find("the replaced one, older than 'topology.csv': delete it"), std::string::npos) << error;
  EXPECT_EQ(entriesUnder(dir),
            (std::set<std::string>{"a", "a/shape.csv", "a/state.csv", ".topology.csv.earlier", "topology.csv"}));
  EXPECT_EQ(readLines(dir / ".topology.csv.earlier"), std::vector<std::string>{"the only copy"});
  EXPECT_EQ(readLines(dir / "topology.csv"), std::vector<std::string>{"earlier"});

  fs::remove(dir / ".topology.csv.earlier");
  ASSERT_EQ(runScenario(scenario, dir.string(), &summary), "");
  EXPECT_EQ(entriesUnder(dir), (std::set<std::string>{"a", "a/shape.csv", "a/state.csv", "b", "b/shape.csv",
                                                      "b/state.csv", "topology.csv"}));
  for (const fs::path& file : earlier)
  {
    EXPECT_NE(readLines(file).at(0), "earlier") << file;
  }

  // A tether's directory that cannot be made (a file named b where it goes) is said before the run, and the files
  // opened before it are removed (a/'s temporaries stayed behind).
  fs::remove_all(dir / "b");
  std::ofstream(dir / "b") << "a file\n";
  const std::string cannot = runScenario(scenario, dir.string(), &summary);
  EXPECT_EQ(cannot.rfind("cannot create output directory '" + (dir / "b").string() + "': ", 0), 0u) << cannot;
  EXPECT_EQ(entriesUnder(dir), (std::set<std::string>{"a", "a/shape.csv", "a/state.csv", "b", "topology.csv"}));
  fs::remove_all(dir);
}

// A state row is written at each output time from the last step before it: rows faster than the steps would
// repeat a step's state under times that were never simulated (a helper's 50 rows per s on 0.1 s steps wrote four
// copies of t = 0 at 0.02-0.08 s). So output_rate above 1 / time_step is refused, naming both, by the library and
// by the runner (exit 2, a bad scenario, whether the file or a --set gives the step); at 1 / time_step it runs.
TEST(Runner, RowsFasterThanTheStepsAreRefused)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.params.time_step = 0.1;
  scenario.output_rate = 10.0;
  EXPECT_EQ(scenario.checkOutputRate(), "");
  scenario.output_rate = 50.0;
  const std::string dir = temporaryDirectory("fast_rows");
  RunSummary summary;
  const std::string error = runScenario(scenario, dir, &summary);
  EXPECT_NE(error.find("output_rate = 50 rows per s is faster than the tether's steps (time_step = 0.1 s: 10 per s)"),
            std::string::npos)
      << error;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "state.csv"));
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::string text = kGood;
  text.replace(text.find("output_rate: 4"), 14, "output_rate: 20");
  std::ofstream(scenario_path) << text;
  EXPECT_EQ(runRunner(scenario_path.string() + " --out " + dir + " --set time_step=0.1"), 2);
  EXPECT_EQ(runRunner(scenario_path.string() + " --out " + dir + " --set time_step=0.05"), 0);  // 20 per s
  fs::remove_all(dir);
  fs::remove(scenario_path);
}

// A row holds the state of the last step at or before its output time, and says that step's time: at 3 rows per s on
// 5 ms steps the rows fall at 0, 0.33, 0.665 and 1 s (a whole number of steps each, within a step before k / 3 s),
// in state.csv and shape.csv alike. They were labelled 0.333333 and 0.666667 s, times never simulated.
TEST(Runner, ARowSaysTheTimeOfTheStateItHolds)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.params.time_step = 0.005;
  scenario.output_rate = 3.0;
  scenario.duration = 1.0;
  const std::string dir = temporaryDirectory("row_times");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  const double h = scenario.params.time_step;
  std::ifstream state(fs::path(dir) / "state.csv");
  std::string line;
  std::getline(state, line);  // the header
  std::vector<double> times;
  while (std::getline(state, line))
  {
    times.push_back(std::stod(line.substr(0, line.find(','))));
  }
  ASSERT_EQ(times.size(), 4u);
  for (std::size_t k = 0; k < times.size(); ++k)
  {
    const double asked = static_cast<double>(k) / scenario.output_rate;
    EXPECT_NEAR(times[k] / h, std::round(times[k] / h), 1e-3) << "row " << k << " at " << times[k] << " s";
    EXPECT_LE(times[k], asked + 1e-9) << "row " << k;
    EXPECT_GT(times[k], asked - h) << "row " << k;
  }
  std::ifstream shape(fs::path(dir) / "shape.csv");
  std::getline(shape, line);
  std::set<double> shape_times;
  while (std::getline(shape, line))
  {
    shape_times.insert(std::stod(line.substr(0, line.find(','))));
  }
  EXPECT_EQ(shape_times, std::set<double>(times.begin(), times.end()));
  fs::remove_all(dir);
}

// The runner warns as the node does (issue 26, item 14): a ROV diving 30 m straight away from a spool on a
// 10 m cable, strain rule, pbd: the cable ends fully deployed and strained far beyond anything real (the
// issue's run read 2.4e6 N at strain 24 without a word). Over-tension above the node's default
// max_tension_warning (500 N) is named with its time; an outrun winch too. A quiet run gives no warning.
TEST(Runner, WarnsOfOverTensionAndAnOutrunWinchAsTheNodeDoes)
{
  const std::string dir = temporaryDirectory("warn");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << "params: {cable_length: 10.0, initial_deployed_length: 2.0, winch_mode: brake, "
                                  "brake_tension: 5.0, max_winch_speed: 0.5, noise: 0.0}\n"
                                  "spool: [0, 0, 0]\nvehicle: [[0, 1.5, 0, 0], [10, 31.5, 0, 0]]\n"
                                  "duration: 10\noutput_rate: 10\n";
  const std::string err = dir + "_stderr.txt";
  const auto runKeepingStderr = [&](const std::string& arguments) { return runRunnerKeepingStderr(arguments, err); };
  EXPECT_EQ(runKeepingStderr(scenario_path.string() + " --out " + dir), 0);
  std::string text;
  for (const std::string& line : readLines(err))
  {
    text += line + "\n";
  }
  EXPECT_NE(text.find("rov_tether_run: warning: over-tension: "), std::string::npos) << text;
  EXPECT_NE(text.find("above max_tension_warning = 500 N"), std::string::npos) << text;
  EXPECT_NE(text.find("the vehicle outruns the winch"), std::string::npos) << text;
  // The same figures through the library: the warnings name what the summary holds.
  Scenario scenario;
  ASSERT_EQ(loadScenario(scenario_path.string(), &scenario), "");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir + "_lib", &summary), "");
  EXPECT_GT(summary.max_tension, 500.0);
  EXPECT_GT(summary.outrun_seconds, 0.0);
  EXPECT_EQ(runWarnings(scenario, summary, 1e12).size(), 1u);  // above every tension: only the outrun
  EXPECT_LT(summary.first_full_time, 0.0);  // 7 m of the 10 out at the end: the cable did not run out
  // Running out of cable is said as such (it read as an outrun winch, or not at all): 3 m of cable, 2 m out, the
  // vehicle driving away at 1 m/s from 1.5 m, its brake (5 N on a weightless cable) paying out as fast as it goes
  // (max_winch_speed 2 m/s: never outrun). The cable, nearly straight, runs out when the vehicle is 3 m out
  // plus the brake's stretch (3 m x 5 N / EA, a few mm): just after t = 1.5 s (the step that pays out the last of
  // it), or up to 0.1 s sooner for its sag.
  std::ofstream(scenario_path) << "params: {cable_length: 3.0, initial_deployed_length: 2.0, winch_mode: brake, "
                                  "brake_tension: 5.0, max_winch_speed: 2.0, weight_in_water: 0.0, noise: 0.0}\n"
                                  "spool: [0, 0, 0]\nvehicle: [[0, 1.5, 0, 0], [3, 4.5, 0, 0]]\n"
                                  "duration: 3\noutput_rate: 10\n";
  ASSERT_EQ(loadScenario(scenario_path.string(), &scenario), "");
  ASSERT_EQ(runScenario(scenario, dir + "_out", &summary), "");
  EXPECT_GE(summary.first_full_time, 1.4 - 1e-9);
  EXPECT_LE(summary.first_full_time, 1.6 + 1e-9);
  EXPECT_EQ(summary.outrun_seconds, 0.0);
  const std::vector<std::string> out = runWarnings(scenario, summary, 1e12);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].rfind("the cable runs out at t = 1.", 0), 0u) << out[0];
  EXPECT_NE(out[0].find("all of cable_length = 3 m is paid out"), std::string::npos) << out[0];
  // A brake winch and a ROV that moves 1 m at 0.5 m/s is quiet.
  std::ofstream(scenario_path) << "spool: [0, 0, 0]\nvehicle: [[0, 1.5, 0, 0], [2, 2.5, 0, 0]]\nduration: 3\n";
  EXPECT_EQ(runKeepingStderr(scenario_path.string() + " --out " + dir + "_quiet"), 0);
  EXPECT_TRUE(readLines(err).empty()) << readLines(err).front();
  EXPECT_EQ(runRunner(scenario_path.string() + " --out " + dir + "_quiet --max-tension-warning x"), 2);
  for (const std::string& d : {dir, dir + "_lib", dir + "_quiet", dir + "_out"})
  {
    fs::remove_all(d);
  }
  fs::remove(scenario_path);
  fs::remove(err);
}

// With `tethers:`, --set was also applied to the scenario's own parameters, which such a run does not use, and
// checked against them: two 80 m tethers refused initial_deployed_length=15 as beyond "cable_length = 10", a
// length the scenario never gave. It applies to each tether now, and a refusal names the tether.
TEST(Runner, SetWithTethersAppliesToEachTetherAndNamesTheOneThatRefuses)
{
  const std::string dir = temporaryDirectory("set_tethers");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << "duration: 0.1\n"
                                  "tethers:\n"
                                  "  - {name: a, spool: [0, 0, 0], vehicle: [[0, 1.5, 0, 0], [1, 2, 0, 0]],\n"
                                  "     params: {cable_length: 80}}\n"
                                  "  - {name: b, spool: [5, 0, 0], vehicle: [[0, 6.5, 0, 0], [1, 7, 0, 0]],\n"
                                  "     params: {cable_length: 20}}\n";
  const std::string err = dir + "_stderr.txt";
  const std::string run = scenario_path.string() + " --out " + dir;
  const auto runKeepingStderr = [&](const std::string& more) { return runRunnerKeepingStderr(run + more, err); };
  EXPECT_EQ(runKeepingStderr(" --set initial_deployed_length=15"), 0);  // within both tethers' cable
  const std::vector<std::string> state = readLines(dir + "/a/state.csv");
  ASSERT_GT(state.size(), 1u);
  EXPECT_EQ(runKeepingStderr(" --set initial_deployed_length=30"), 2);  // beyond b's 20 m
  const std::vector<std::string> lines = readLines(err);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.front().find("--set, tether b: "), std::string::npos) << lines.front();
  EXPECT_NE(lines.front().find("cable_length = 20"), std::string::npos) << lines.front();
  fs::remove_all(dir);
  fs::remove(scenario_path);
  fs::remove(err);
}

// An option or a --set parameter given twice on the runner's command line is refused naming it and both values
// (the rule for duplicate keys, as a scenario file's), not the first dropped without a word; two different
// parameters are two assignments.
TEST(Runner, RefusesAnOptionOrAParameterGivenTwice)
{
  const std::string dir = temporaryDirectory("twice");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << "spool: [0, 0, 0]\nvehicle: [[0, 1.5, 0, 0], [1, 2.0, 0, 0]]\nduration: 0.1\n";
  const std::string err = dir + "_stderr.txt";
  const std::string run = scenario_path.string() + " --out " + dir;
  const auto runKeepingStderr = [&](const std::string& more) { return runRunnerKeepingStderr(run + more, err); };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {" --set noise=0.001 --set=noise=0.002", "--set noise given twice ('noise=0.001' and 'noise=0.002')"},
      {" --set 'noise =0.001' --set noise=0.002", "--set noise given twice ('noise =0.001' and 'noise=0.002')"},
      {" --out " + dir + "_other", "--out given twice ('" + dir + "' and '" + dir + "_other')"},
      {" --max-tension-warning 5 --max-tension-warning=6", "--max-tension-warning given twice ('5' and '6')"}};
  for (const auto& [twice, named] : cases)
  {
    EXPECT_EQ(runKeepingStderr(twice), 2) << twice;
    const std::vector<std::string> lines = readLines(err);
    ASSERT_FALSE(lines.empty()) << twice;
    EXPECT_NE(lines.front().find(named), std::string::npos) << lines.front();
  }
  EXPECT_FALSE(fs::exists(dir));  // refused before anything ran
  EXPECT_EQ(runKeepingStderr(" --set noise=0.001 --set drag=0.8"), 0);
  EXPECT_TRUE(fs::exists(dir + "/state.csv"));
  fs::remove_all(dir);
  fs::remove(scenario_path);
  fs::remove(err);
}

// rov_tether_study likewise refuses an option given twice (scripts/study.sh passes its own --out before the
// user's arguments, where a second --out silently won), with the usage and exit code 2, before running anything.
TEST(StudyTool, RefusesAnOptionGivenTwice)
{
  const std::string dir = temporaryDirectory("study_twice");
  const std::string err = dir + "_stderr.txt";
  for (const std::string& twice : {" --out " + dir + " --out " + dir + "_other", " --out " + dir + " --quick --quick"})
  {
    const int status = std::system((std::string(ROV_TETHER_STUDY) + twice + " >/dev/null 2> " + err).c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << twice;
    const std::vector<std::string> lines = readLines(err);
    ASSERT_FALSE(lines.empty()) << twice;
    EXPECT_NE(lines.front().find(" given twice: give it once"), std::string::npos) << lines.front();
  }
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_FALSE(fs::exists(dir + "_other"));
  fs::remove(err);
}

/// The fields of a CSV line (no quoting: the study's lines have none).
std::vector<std::string> commaSeparated(const std::string& line)
{
  std::vector<std::string> fields;
  std::stringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');)
  {
    fields.push_back(field);
  }
  return fields;
}

// An unknown --case is refused with exit code 2, naming the cases there are, before anything runs (it ran no
// case and wrote a study.csv of the header alone, with exit code 0).
TEST(StudyTool, RefusesAnUnknownCase)
{
  const std::string dir = temporaryDirectory("study_unknown_case");
  const std::string err = dir + "_stderr.txt";
  const int status = std::system((std::string(ROV_TETHER_STUDY) + " --out " + dir +
                                  " --case catenary_s9 --quick --no-stability >/dev/null 2> " + err)
                                     .c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
  const std::vector<std::string> lines = readLines(err);
  ASSERT_FALSE(lines.empty());
  EXPECT_NE(lines.front().find("no case called 'catenary_s9'"), std::string::npos) << lines.front();
  for (const rov_tether::study::Case& c : rov_tether::study::cases())
  {
    EXPECT_NE(lines.front().find(c.name), std::string::npos) << c.name << ": " << lines.front();
  }
  EXPECT_FALSE(fs::exists(dir));
  fs::remove_all(dir);
  fs::remove(err);
}

// A stability.csv that cannot be written (a directory in its place) is said as study.csv's is, "cannot write
// 'PATH': ..." with exit code 1, before the study runs (its fopen was unchecked: the tool crashed after the whole
// study), and an earlier run's study.csv stays as it was (it was truncated, then removed).
TEST(StudyTool, SaysWhenItCannotWriteTheStabilityMap)
{
  const std::string dir = temporaryDirectory("study_no_stability_csv");
  const std::string err = dir + "_stderr.txt";
  fs::create_directories(dir + "/stability.csv");
  {
    std::ofstream earlier(dir + "/study.csv");
    earlier << "an earlier run\n";
  }
  const int status = std::system(
      (std::string(ROV_TETHER_STUDY) + " --out " + dir + " --case taut_string --quick >/dev/null 2> " + err).c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  const std::vector<std::string> lines = readLines(err);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front(), "rov_tether_study: cannot write '" + dir + "/stability.csv': it is a directory");
  EXPECT_EQ(readLines(dir + "/study.csv"), std::vector<std::string>{"an earlier run"});  // nothing ran
  fs::remove_all(dir);
  fs::remove(err);
}

// The automatic choice (the study's stars, docs/accuracy.md) is pbd's, the paper's solver, whose iterations
// `iterations: auto` chooses from the stretch tolerance: 20 segments for 1 cm chords and 61 for 1 mm
// (docs/references.md), more iterations for 0.1% stretch than for 1%. It ran the default solver (direct).
TEST(StudyTool, TheAutomaticChoiceIsPbds)
{
  const std::string dir = temporaryDirectory("study_auto");
  ASSERT_EQ(std::system((std::string(ROV_TETHER_STUDY) + " --out " + dir +
                         " --case catenary_s8 --quick --no-stability >/dev/null")
                            .c_str()),
            0);
  std::vector<std::vector<std::string>> autos;  // method, segments, iterations
  for (const std::string& line : readLines(dir + "/study.csv"))
  {
    const std::vector<std::string> fields = commaSeparated(line);
    if (line.size() > 5 && line.substr(line.size() - 5) == ",auto")
    {
      autos.push_back({fields.at(1), fields.at(2), fields.at(3)});
    }
  }
  EXPECT_FALSE(fs::exists(dir + "/.study.csv.partial"));  // moved into place
  // Shape 1 cm then 1 mm, each with stretch 1% then 0.1%.
  ASSERT_EQ(autos.size(), 4u);
  for (std::size_t i = 0; i < autos.size(); ++i)
  {
    EXPECT_EQ(autos[i][0], "pbd") << i;
    EXPECT_EQ(autos[i][1], i < 2 ? "20" : "61") << i;
  }
  EXPECT_LT(std::stoi(autos[0][2]), std::stoi(autos[1][2]));
  EXPECT_LT(std::stoi(autos[2][2]), std::stoi(autos[3][2]));
  fs::remove_all(dir);
}

// The paper's experiment keeps its own step (0.02 s): each method x resolution x effort runs once at it. The
// efforts' three steps ran every configuration three times (189 rows, 69 of them distinct).
TEST(StudyTool, RunsEachConfigurationOfThePapersExperimentOnce)
{
  const std::string dir = temporaryDirectory("study_paper");
  ASSERT_EQ(std::system(
                (std::string(ROV_TETHER_STUDY) + " --out " + dir + " --case paper_experiment --no-stability >/dev/null")
                    .c_str()),
            0);
  std::set<std::string> configurations;
  int rows = 0;
  for (const std::string& line : readLines(dir + "/study.csv"))
  {
    const std::vector<std::string> fields = commaSeparated(line);
    ASSERT_GE(fields.size(), 7u) << line;
    if (fields[0] != "paper_experiment")
    {
      continue;  // the header
    }
    ++rows;
    EXPECT_EQ(fields[6], "0.02") << line;
    // method, segments, iterations, substeps, over_relaxation, time_step
    EXPECT_TRUE(
        configurations
            .insert(fields[1] + "," + fields[2] + "," + fields[3] + "," + fields[4] + "," + fields[5] + "," + fields[6])
            .second)
        << "run twice: " << line;
  }
  // 3 resolutions x (pbd 12 efforts, xpbd 7, lumped_mass 3, direct 1).
  EXPECT_EQ(rows, 3 * (12 + 7 + 3 + 1));
  fs::remove_all(dir);
}

// The run's Newton effort (issue 24): by definition the sum, the largest and the worst residual of what the
// solver reported after each sub-step. A direct tether stepped by hand, reading solverIterations() and
// solverResidual() after every step (one sub-step each: no contact), gives exactly what solverEffort() summed;
// each sub-step takes at least one iteration and at most `iterations` (none diverges here, so none is rescued past
// them: SolverEffort::rescued 0). The runner's summary carries it and
// prints its "newton" line for direct, and neither for pbd (which reports no iterations).
TEST(Runner, ReportsTheNewtonEffortTheSolverTook)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.params.solver = SolverType::kDirect;
  Tether tether(scenario.params, scenario.spool, scenario.vehicleAt(0.0));
  std::uint64_t iterations = 0;
  int most = -1;
  double worst = 0.0;
  const int steps = 400;
  for (int i = 0; i < steps; ++i)
  {
    ASSERT_TRUE(tether.addVehicleSample(0.005 * (i + 1), scenario.vehicleAt(0.005 * (i + 1))).ok);
    tether.step();
    iterations += static_cast<std::uint64_t>(tether.solverIterations());
    most = std::max(most, tether.solverIterations());
    worst = std::max(worst, tether.solverResidual());
  }
  const SolverEffort& effort = tether.solverEffort();
  EXPECT_EQ(effort.substeps, static_cast<std::uint64_t>(steps));
  EXPECT_EQ(effort.iterations, iterations);
  EXPECT_EQ(effort.max_iterations, most);
  EXPECT_EQ(effort.max_residual, worst);
  EXPECT_GE(effort.meanIterations(), 1.0);
  EXPECT_LE(effort.max_iterations, scenario.params.iterations);
  EXPECT_EQ(effort.rescued, 0u);

  const std::string dir = temporaryDirectory("newton");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  EXPECT_EQ(summary.solver.substeps, summary.steps);
  EXPECT_GE(summary.solver.max_iterations, 1);
  // state.csv's last three columns are each row's share of that effort (the sub-steps since the row before,
  // as many for every row at a fixed output rate): the rows' means average to the run's mean, and their
  // maxima and residuals peak at the run's, within the printed digits (4 and 3 significant).
  const auto newtonColumns = [](const fs::path& state)
  {
    std::vector<std::array<double, 3>> rows;
    for (const std::string& line : readLines(state))
    {
      const std::size_t c3 = line.rfind(','), c2 = line.rfind(',', c3 - 1), c1 = line.rfind(',', c2 - 1);
      if (line.rfind("t,", 0) != 0)
      {
        rows.push_back({std::stod(line.substr(c1 + 1, c2 - c1 - 1)), std::stod(line.substr(c2 + 1, c3 - c2 - 1)),
                        std::stod(line.substr(c3 + 1))});
      }
    }
    return rows;
  };
  const auto rows = newtonColumns(fs::path(dir) / "state.csv");
  ASSERT_GT(rows.size(), 2u);
  EXPECT_TRUE(std::isnan(rows[0][0])) << "t = 0 comes before any sub-step";
  double mean_sum = 0.0, most_seen = 0.0, worst_seen = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i)
  {
    mean_sum += rows[i][0];
    most_seen = std::max(most_seen, rows[i][1]);
    worst_seen = std::max(worst_seen, rows[i][2]);
  }
  EXPECT_NEAR(mean_sum / static_cast<double>(rows.size() - 1), summary.solver.meanIterations(),
              1e-3 * summary.solver.meanIterations());
  EXPECT_EQ(most_seen, summary.solver.max_iterations);
  EXPECT_NEAR(worst_seen, summary.solver.max_residual, 5e-3 * summary.solver.max_residual);
  // Each row covers its own sub-steps, not the run so far: a cable snapped taut at 2 m/s (the hard steps)
  // and then held still for 4 s converges at once, so the last row's most iterations and residual fall below
  // the run's (a row that carried the run's figures would keep them to the end).
  {
    const fs::path snap_path = fs::path(dir + "_snap.yaml");
    std::ofstream(snap_path) << "params: {solver: direct, noise: 0.0, winch_mode: locked, cable_length: 3.0, "
                                "initial_deployed_length: 3.0}\nspool: [0, 0, 0]\n"
                                "vehicle: [[0, 1.0, 0, 0], [1, 3.0, 0, 0], [5, 3.0, 0, 0]]\nduration: 5\n"
                                "output_rate: 4\n";
    Scenario snap;
    ASSERT_EQ(loadScenario(snap_path.string(), &snap), "");
    RunSummary snap_summary;
    ASSERT_EQ(runScenario(snap, dir + "_snap", &snap_summary), "");
    const auto snap_rows = newtonColumns(fs::path(dir + "_snap") / "state.csv");
    ASSERT_GT(snap_rows.size(), 10u);
    std::printf("[ measured ] snap then still: the run at most %d iterations, residual %.3g; its last row %g, %g\n",
                snap_summary.solver.max_iterations, snap_summary.solver.max_residual, snap_rows.back()[1],
                snap_rows.back()[2]);
    EXPECT_LT(snap_rows.back()[1], snap_summary.solver.max_iterations);
    EXPECT_LT(snap_rows.back()[2], 0.5 * snap_summary.solver.max_residual);
    fs::remove_all(dir + "_snap");
    fs::remove(snap_path);
  }
  scenario.params.solver = SolverType::kPbd;
  ASSERT_EQ(runScenario(scenario, dir + "_pbd", &summary), "");
  EXPECT_EQ(summary.solver.substeps, 0u);
  EXPECT_TRUE(std::isnan(summary.solver.meanIterations()));
  for (const auto& row : newtonColumns(fs::path(dir + "_pbd") / "state.csv"))
  {
    EXPECT_TRUE(std::isnan(row[0]) && std::isnan(row[1]) && std::isnan(row[2])) << "pbd reports no Newton effort";
  }
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  for (const auto& [solver, printed] : {std::pair<std::string, bool>{"direct", true}, {"pbd", false}})
  {
    std::ofstream(scenario_path) << "params: {solver: " << solver << "}\nspool: [0, 0, 0]\n"
                                 << "vehicle: [[0, 1.5, 0, 0], [2, 2.5, 0, 0]]\nduration: 0.5\n";
    const std::string out = dir + "_summary.txt";
    ASSERT_EQ(std::system((std::string(ROV_TETHER_RUNNER) + " " + scenario_path.string() + " --out " + dir + "_" +
                           solver + "_cli > " + out + " 2>&1")
                              .c_str()),
              0);
    bool found = false;
    for (const std::string& line : readLines(out))
    {
      found = found || line.rfind("newton          ", 0) == 0;
    }
    EXPECT_EQ(found, printed) << solver;
    fs::remove(out);
    fs::remove_all(dir + "_" + solver + "_cli");
  }
  fs::remove(scenario_path);
  fs::remove_all(dir);
  fs::remove_all(dir + "_pbd");
}

// A sub-step that stops with its residual above solver_tolerance is counted (SolverEffort::unconverged), with the
// last one's residual and iterations: by definition, the steps whose solverResidual() is above the tolerance.
// With one Newton iteration a step, a moving cable's steps stop short: a Newton step from the warm start leaves
// at least the segments' second-order stretch (a segment's chord against its arc), far above the 1e-8
// tolerance, so the count is not 0. With kGood's limit (5) none does here (the same count, 0). The runner's
// summary carries the count.
TEST(Runner, CountsTheSubStepsThatStopShortOfTheTolerance)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  scenario.params.solver = SolverType::kDirect;
  for (const int limit : {1, scenario.params.iterations})
  {
    TetherParams params = scenario.params;
    params.iterations = limit;
    Tether tether(params, scenario.spool, scenario.vehicleAt(0.0));
    std::uint64_t short_of = 0;
    double last_residual = std::numeric_limits<double>::quiet_NaN();
    int last_iterations = -1;
    for (int i = 0; i < 400; ++i)
    {
      ASSERT_TRUE(tether.addVehicleSample(0.005 * (i + 1), scenario.vehicleAt(0.005 * (i + 1))).ok);
      tether.step();
      if (tether.solverResidual() > params.solver_tolerance)
      {
        ++short_of;
        last_residual = tether.solverResidual();
        last_iterations = tether.solverIterations();
      }
    }
    const SolverEffort& effort = tether.solverEffort();
    std::printf(
        "[ measured ] at most %d iteration%s a step: %llu of 400 steps short of the tolerance, residual up to "
        "%.3g\n",
        limit, limit == 1 ? "" : "s", static_cast<unsigned long long>(effort.unconverged), effort.max_residual);
    EXPECT_EQ(effort.unconverged, short_of);
    if (limit == 1)
    {
      EXPECT_GT(short_of, 0u) << "one iteration a step converged every step: this tests nothing";
      EXPECT_EQ(effort.unconverged_residual, last_residual);
      EXPECT_EQ(effort.unconverged_iterations, last_iterations);
      EXPECT_EQ(last_iterations, 1);
    }
    else
    {
      EXPECT_EQ(short_of, 0u);
      EXPECT_TRUE(std::isnan(effort.unconverged_residual));
      EXPECT_EQ(effort.unconverged_iterations, -1);
    }
  }
  scenario.params.iterations = 1;
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, temporaryDirectory("short_of_tolerance"), &summary), "");
  EXPECT_GT(summary.solver.unconverged, 0u);
  EXPECT_LE(summary.solver.unconverged, summary.solver.substeps);
}

// A path that starts out of the tether's reach (30 m out on a locked winch with 8 m out) is said when the world is
// built, as a dynamic vehicle's start out of reach is (VehicleCoupling.OnlyDirectTakesADynamicVehicle...): the
// distance, the cable there is, the strain it is laid at, (30 - 8) / 8 = 2.75, and that the path starts out of
// reach, named by its tether among several. It was said only as an over-tension. A path within reach says nothing.
// It is said to the caller, in buildWorld's warnings, and nothing is written to stderr (the library printed it there,
// so a Python user saw raw C stderr): the runner's summary lists it with its other warnings (runWarnings).
TEST(Runner, APathStartingOutOfTheTethersReachIsSaid)
{
  const std::string tether =
      "params: {winch_mode: locked, initial_deployed_length: 8.0, noise: 0.0}\n"
      "spool: [0, 0, 0]\nvehicle: [[0, 30, 0, 0], [1, 30, 0, 0]]\n";
  const std::string message =
      "vehicle: the vehicle's first position is 30 m from the spool, beyond the 8 m of cable "
      "the locked winch has out: the cable is laid stretched to it (strain 2.75): its path "
      "starts out of the tether's reach\n";
  const auto said = [](const std::string& yaml)
  {
    Scenario scenario;
    EXPECT_EQ(parseScenario(yaml, &scenario), "");
    World world;
    std::vector<std::string> warnings;
    testing::internal::CaptureStderr();
    EXPECT_EQ(buildWorld(worldSpecOf(scenario), &world, &warnings), "");
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << "nothing on stderr";
    std::string text;
    for (const std::string& warning : warnings)
    {
      text += warning + "\n";
    }
    return text;
  };
  EXPECT_EQ(said(tether + "duration: 1\n"), message);
  std::string two =
      "duration: 1\ntethers:\n  - name: near\n    spool: [0, 0, 0]\n    vehicle: [[0, 1, 0, 0]]\n"
      "  - name: far\n";
  for (std::size_t line = 0, next = 0; line < tether.size(); line = next + 1)
  {
    next = tether.find('\n', line);
    two += "    " + tether.substr(line, next - line + 1);
  }
  EXPECT_EQ(said(two), "tether far: " + message);
  EXPECT_EQ(said("spool: [0, 0, 0]\nvehicle: [[0, 7, 0, 0]]\nduration: 1\n"), "");

  Scenario scenario;
  ASSERT_EQ(parseScenario(tether + "duration: 0.1\n", &scenario), "");
  RunSummary summary;
  testing::internal::CaptureStderr();
  ASSERT_EQ(runScenario(scenario, temporaryDirectory("out_of_reach"), &summary), "");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << "nothing on stderr";
  const std::vector<std::string> warnings = runWarnings(scenario, summary, kDefaultMaxTensionWarning);
  ASSERT_FALSE(warnings.empty());
  EXPECT_EQ(warnings.front() + "\n", message);
}

// A vehicle jump that lands out of the cable's reach is said by the runner, as the node warns of it (69c511e;
// VehicleJump.AJumpOutOfTheCablesReachIsSaid): a path 5 m out on a locked 8 m cable that jumps to 30 m between
// t = 1 s and 1.005 s (25 m in 5 ms, far beyond max_vehicle_speed x dt + max_vehicle_jump = 1.015 m) is re-laid
// stretched to it, at (30 - 8) / 8 = 2.75, and the warning gives the count, the time of the step that said it (the
// jump's, within its 5 ms step: 1.005 or 1.01 s, printed 1.00 or 1.01) and the tether's words. It was said only as
// an over-tension. A jump within reach (to 7 m) is a jump and says nothing; a path that starts out of reach is said
// once, as the world's warning when it is built (Runner.APathStartingOutOfTheTethersReachIsSaid), not again.
TEST(Runner, AJumpOutOfTheCablesReachIsSaid)
{
  const auto run = [](double to, RunSummary* summary)
  {
    Scenario scenario;
    const std::string yaml =
        "params: {winch_mode: locked, cable_length: 8.0, initial_deployed_length: 8.0, noise: 0.0}\n"
        "spool: [0, 0, 0]\nvehicle: [[0, 5, 0, 0], [1, 5, 0, 0], [1.005, " +
        std::to_string(to) + ", 0, 0], [2, " + std::to_string(to) + ", 0, 0]]\nduration: 2\n";
    EXPECT_EQ(parseScenario(yaml, &scenario), "");
    const std::string dir = temporaryDirectory("jump_out_of_reach");
    EXPECT_EQ(runScenario(scenario, dir, summary), "");
    fs::remove_all(dir);
    return runWarnings(scenario, *summary, 1e12);  // over-tension left out: above every tension
  };
  RunSummary summary;
  std::vector<std::string> warnings = run(30.0, &summary);
  EXPECT_EQ(summary.jumps, 1u);
  EXPECT_EQ(summary.out_of_reach, 1u);
  EXPECT_GE(summary.first_out_of_reach_time, 1.005 - 1e-9);
  EXPECT_LE(summary.first_out_of_reach_time, 1.01 + 1e-9);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("vehicle out of the cable's reach (1) from t = 1.0", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find(" s, the last: the vehicle's pose after a jump is 30 m from the spool, beyond the 8 m of "
                             "cable the locked winch has out: the cable is laid stretched to it (strain 2.75): it "
                             "jumped out of the tether's reach"),
            std::string::npos)
      << warnings[0];
  warnings = run(7.0, &summary);
  EXPECT_EQ(summary.jumps, 1u);
  EXPECT_EQ(summary.out_of_reach, 0u);
  EXPECT_TRUE(warnings.empty()) << warnings.front();

  Scenario scenario;
  ASSERT_EQ(parseScenario("params: {winch_mode: locked, initial_deployed_length: 8.0, noise: 0.0}\n"
                          "spool: [0, 0, 0]\nvehicle: [[0, 30, 0, 0], [1, 30, 0, 0]]\nduration: 0.1\n",
                          &scenario),
            "");
  const std::string dir = temporaryDirectory("start_out_of_reach");
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  fs::remove_all(dir);
  EXPECT_EQ(summary.out_of_reach, 0u);
  EXPECT_EQ(runWarnings(scenario, summary, 1e12).size(), 1u) << "the world's warning alone";
}

// A `speed` winch reeling in at 0.5 m/s against a ROV that holds still 9 m out on 10 m: once the slack is in, the
// motor's stall pull (7.5 N, derived: 1.25 x (5 + 1)) holds it, and the runner says so as the node does, with the
// first output time it was held (Tether::winchStalled), the speed and the pull. The slack is in by 2.25 s at the
// latest (the drum at 0.5 m/s after 0.5 s at 1 m/s^2: 0.125 m, then 0.875 m at 0.5 m/s; the drag on the moving
// slack can hold it sooner), held 0.2 s (kOutrunTime) it is said: from the step that ends at 2.45 s at the latest,
// so for 5 - 2.45 = 2.55 s at least. Paying out at 0.5 m/s to the same ROV is no stall. Said from the steps, not the
// output rows: at one row every 2 s to 3 s (rows at 0 and 2 s, the stall after both) it is said all the same, from
// the same step (it read no stall: the rows held none).
TEST(Runner, WarnsOfAReelInHeldAtTheStallPull)
{
  const std::string yaml =
      "params: {cable_length: 40.0, initial_deployed_length: 10.0, winch_mode: speed, "
      "winch_speed: -0.5, max_winch_speed: 3.0, bending_stiffness: 0.0, noise: 0.0}\n"
      "spool: [0, 0, 0]\nvehicle: [[0, 9, 0, 0], [5, 9, 0, 0]]\nduration: 5\noutput_rate: 10\n";
  Scenario scenario;
  ASSERT_EQ(parseScenario(yaml, &scenario), "");
  const std::string dir = temporaryDirectory("stall");
  RunSummary summary;
  ASSERT_EQ(runScenario(scenario, dir, &summary), "");
  fs::remove_all(dir);
  const std::vector<std::string> warnings = runWarnings(scenario, summary, kDefaultMaxTensionWarning);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("the winch cannot reel in at its commanded -0.5 m/s"), std::string::npos) << warnings[0];
  EXPECT_GT(summary.first_stall_time, Tether::kOutrunTime);
  EXPECT_LE(summary.first_stall_time, 2.45 + 1e-9);
  const double first_stall = summary.first_stall_time;
  EXPECT_NE(warnings[0].find("stall pull of 7.5 N (max_winch_pull 0: 1.25 x"), std::string::npos) << warnings[0];
  EXPECT_GE(summary.stall_seconds, 5.0 - 2.45 - 1e-9);
  Scenario sparse_rows = scenario;
  sparse_rows.output_rate = 0.5;
  sparse_rows.duration = 3.0;
  ASSERT_EQ(runScenario(sparse_rows, dir, &summary), "");
  fs::remove_all(dir);
  ASSERT_EQ(summary.state_rows, 2u);  // t = 0 and 2 s
  EXPECT_DOUBLE_EQ(summary.first_stall_time, first_stall);
  EXPECT_GT(first_stall, 2.0) << "said after the last row (2 s), or this part does not test the steps past it";
  EXPECT_GE(summary.stall_seconds, 3.0 - 2.45 - 1e-9);
  EXPECT_EQ(runWarnings(sparse_rows, summary, kDefaultMaxTensionWarning).size(), 1u);
  Scenario paying_out = scenario;
  paying_out.params.winch_speed = 0.5;
  ASSERT_EQ(runScenario(paying_out, dir, &summary), "");
  fs::remove_all(dir);
  EXPECT_EQ(summary.stall_seconds, 0.0);
  EXPECT_TRUE(runWarnings(paying_out, summary, kDefaultMaxTensionWarning).empty());
}

// Every shipped scenario (scenarios/ and scenarios/datasets/, worlds included) loads without a deprecation
// warning and runs without a simulation failure, over-tension (the node's default 500 N) or an outrun winch
// (issue 26, item 15: forward_camera_dive used the deprecated `passive` and read 9.6 kN at 9.6% strain).
// Cameras are left out: looking changes nothing in the run (Dataset.RunnerWritesMasksDepthAndAnIndex...).
TEST(ShippedFiles, EveryScenarioRunsWithoutFailuresOrWarnings)
{
  int runs = 0;
  for (const auto& entry : fs::recursive_directory_iterator(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios"))
  {
    if (!entry.is_regular_file() || entry.path().extension() != ".yaml")
    {
      continue;
    }
    Scenario scenario;
    testing::internal::CaptureStderr();
    const std::string error = loadScenario(entry.path().string(), &scenario);
    const std::string warnings = testing::internal::GetCapturedStderr();
    ASSERT_EQ(error, "") << entry.path();
    EXPECT_EQ(warnings, "") << entry.path();
    scenario.cameras.clear();
    const std::string dir = temporaryDirectory("shipped_" + entry.path().stem().string());
    RunSummary summary;
    ASSERT_EQ(runScenario(scenario, dir, &summary), "") << entry.path();
    std::string said;
    for (const std::string& warning : runWarnings(scenario, summary, kDefaultMaxTensionWarning))
    {
      said += warning + "\n";
    }
    EXPECT_EQ(said, "") << entry.path();
    std::printf("[ measured ] %s: max tension %.4g N, max strain %.4g\n", entry.path().filename().c_str(),
                summary.max_tension, summary.max_strain);
    fs::remove_all(dir);
    ++runs;
  }
  EXPECT_GE(runs, 9);
}

// A world's scenario: two tethers and two obstacles, contact between tethers on.
const std::string kWorld = R"(
duration: 1
output_rate: 10
tether_contact: true
tethers:
  - name: a
    params: {iterations: 3, noise: 0.002}
    spool: [0, -0.5, 0]
    vehicle: [[0, 3, -0.5, 0], [1, 3, 0.5, 0]]
  - name: b
    spool: [0, 0.5, 0]
obstacles:
  - {name: pillar, type: cylinder, position: [1.5, 0, 0], orientation: [0, 0, 0.5], radius: 0.2, length: 4}
  - {name: rock, type: box, position: [1, 1, -1], size: [0.5, 0.4, 0.3], friction: 0.8}
)";

TEST(ScenarioFile, ParsesTethersObstaclesAndContact)
{
  Scenario scenario;
  ASSERT_EQ(parseScenario(kWorld, &scenario), "");
  EXPECT_TRUE(scenario.tether_contact);
  EXPECT_TRUE(scenario.usesWorld());
  ASSERT_EQ(scenario.tethers.size(), 2u);
  EXPECT_EQ(scenario.tethers[0].name, "a");
  EXPECT_EQ(scenario.tethers[0].params.iterations, 3);
  EXPECT_EQ(scenario.tethers[0].spool, Position(0, -0.5, 0));
  ASSERT_EQ(scenario.tethers[0].vehicle.size(), 2u);
  EXPECT_EQ(scenario.tethers[1].params.iterations, TetherParams{}.iterations);  // each its own, from the defaults
  EXPECT_TRUE(scenario.tethers[1].vehicle.empty());
  ASSERT_EQ(scenario.obstacles.size(), 2u);
  EXPECT_EQ(scenario.obstacles[0].type, ShapeType::Cylinder);
  EXPECT_EQ(scenario.obstacles[0].orientation, Eigen::Vector3d(0, 0, 0.5));
  EXPECT_EQ(scenario.obstacles[0].friction, 0.5);  // the default
  EXPECT_EQ(scenario.obstacles[1].size, Eigen::Vector3d(0.5, 0.4, 0.3));
  EXPECT_EQ(scenario.obstacles[1].friction, 0.8);
  // Without the new keys a scenario is what it was: one tether, no world, no topology.csv.
  ASSERT_EQ(parseScenario(kGood, &scenario), "");
  EXPECT_FALSE(scenario.usesWorld());
  EXPECT_FALSE(scenario.tether_contact);  // the node's default
}

TEST(ScenarioFile, BadTethersAndObstaclesNameTheEntryAndTheField)
{
  const std::string head = "spool: [0, 0, 0]\nduration: 1\nobstacles:\n";
  const std::string tethers = "duration: 1\ntethers:\n  - {name: a, spool: [0, 0, 0]}\n";
  const std::vector<BadScenario> cases = {
      {head + "  - {name: p, type: cone, radius: 1}", "obstacles[0] 'p' type: expected sphere, box, cylinder"},
      {head + "  - {name: p, type: cylinder, length: 2}", "obstacles[0]: obstacle 'p' (cylinder): radius must be > 0"},
      {head + "  - {name: p, type: sphere, radius: 1, frame: buoy}", "obstacles[0] 'p' frame: node only"},
      {head + "  - {name: p, type: sphere, radius: 1}\n  - {name: p, type: sphere, radius: 2}",
       "obstacles[1] 'p' name: taken by an earlier obstacle"},
      {head + "  - {name: tether, type: sphere, radius: 1}", "obstacles[0] 'tether' name: taken by a tether"},
      {head + "  - {type: sphere, radius: 1}", "obstacles[0] name: expected a non-empty string"},
      {head + "  - {name: p, type: sphere, radius: 1, colour: red}", "obstacles[0] 'p': unknown field 'colour'"},
      // A field of another shape is read by nothing: named with what this shape takes.
      {head + "  - {name: p, type: sphere, radius: 1, length: 3}", "obstacles[0] 'p' length: a sphere has no length"},
      {head + "  - {name: p, type: box, size: [1, 1, 1], radius: 1}", "obstacles[0] 'p' radius: a box has no radius"},
      {head + "  - {name: p, type: plane, scale: 2}", "obstacles[0] 'p' scale: a plane has no scale"},
      {head + "  - {name: p, type: sphere, radius: 1, position: [0, 0]}",
       "obstacles[0] 'p' position: expected [x, y, z] in m"},
      {head + "  - {name: p, type: sphere, radius: x}", "obstacles[0] 'p' radius: expected a number"},
      {head + "  - {name: p, type: sphere, radius: 1, friction: 20}", "friction must be in [0, 10]"},
      {head + "  - {name: p, type: mesh, file: 'package://rov_tether/meshes/wreck.stl'}",
       "obstacles[0] 'p' file: expected a path"},
      {head + "  - {name: p, type: sphere, radius: 1e9}", "obstacles[0] 'p': position, radius"},
      {head + "  {name: p}", "obstacles: expected a list"},
      {"spool: [0, 0, 0]\nduration: 1\ntether_contact: maybe", "tether_contact: expected true or false"},
      {tethers + "params: {iterations: 3}", "params: not with `tethers`"},
      {tethers + "spool: [0, 0, 0]", "spool: not with `tethers`"},
      {tethers + "vehicle: [[0, 1, 0, 0]]", "vehicle: not with `tethers`"},
      {tethers + "  - {name: a, spool: [1, 0, 0]}", "tethers[1].name = 'a': used twice"},
      {tethers + "  - {name: 'b/c', spool: [1, 0, 0]}", "tethers[1].name = 'b/c': expected 1-64 letters"},
      {tethers + "  - {name: b}", "tethers[1].spool: missing"},
      {tethers + "  - {name: b, spool: [1, 0, 0], params: {iterations: 0}}", "tethers[1].params.iterations = 0"},
      {tethers + "  - {name: b, spool: [1, 0, 0], vehicle: [[0, 1, 0]]}",
       "tethers[1].vehicle[0]: expected a list of 4 numbers"},
      {tethers + "  - {name: b, spool: [1, 0, 0], winch: locked}", "tethers[1]: unknown field 'winch'"},
      {tethers + "obstacles: [{name: a, type: sphere, radius: 1}]", "obstacles[0] 'a' name: taken by a tether"},
      {"duration: 1\ntethers: []", "tethers: expected a non-empty list"},
  };
  for (const auto& c : cases)
  {
    Scenario scenario;
    const std::string error = parseScenario(c.yaml, &scenario);
    EXPECT_NE(error.find(c.message), std::string::npos) << "yaml: " << c.yaml << "\nerror: " << error;
  }
}

/// The text of a file (empty when it cannot be read).
std::string fileText(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A `tethers` list writes each tether's files in DIR/<name>/ and DIR/topology.csv, nothing in DIR itself; a
// single tether with obstacles keeps DIR/state.csv and DIR/shape.csv, and adds DIR/topology.csv.
TEST(Runner, TethersWriteTheirOwnDirectoriesAndTheWorldItsTopology)
{
  const std::string dir = temporaryDirectory("world");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << kWorld;
  ASSERT_EQ(runRunner(scenario_path.string() + " --out " + dir), 0);
  std::set<std::string> written;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
  {
    written.insert(fs::relative(entry.path(), dir).string());
  }
  EXPECT_EQ(written, (std::set<std::string>{"a", "a/state.csv", "a/shape.csv", "b", "b/state.csv", "b/shape.csv",
                                            "topology.csv"}));
  for (const char* tether : {"a", "b"})
  {
    const auto state = readLines(fs::path(dir) / tether / "state.csv");
    ASSERT_EQ(state.size(), 1u + 11u) << tether;  // header + t = 0, 0.1, ..., 1
    EXPECT_EQ(state[0], kStateCsvHeader);
    EXPECT_EQ(readLines(fs::path(dir) / tether / "shape.csv")[0], kShapeCsvHeader);
  }
  // b hangs from its spool with a free end, 0.5 m off a's: a 3 m tether ends 3 m from its spool.
  EXPECT_EQ(readLines(fs::path(dir) / "a" / "state.csv")[1].rfind("0.000000,3.000000,", 0), 0u);
  fs::remove_all(dir);

  // pillar_wrap.yaml: one tether, an obstacle.
  const std::string pillar = std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/pillar_wrap.yaml";
  ASSERT_EQ(runRunner(pillar + " --out " + dir), 0);
  written.clear();
  for (const auto& entry : fs::recursive_directory_iterator(dir))
  {
    written.insert(fs::relative(entry.path(), dir).string());
  }
  EXPECT_EQ(written, (std::set<std::string>{"state.csv", "shape.csv", "topology.csv"}));
  fs::remove_all(dir);
  fs::remove(scenario_path);
}

// topology.csv: its header; every row at an output time (k / output_rate), of one of the five kinds, naming a
// tether and an object of the scenario; each pair's linking number once per output time, lower index first.
// The two shipped world scenarios together show all five kinds: pillar_wrap the wraps (turns and angle), the
// contact angle and the capstan ratio (its tether lies on the pillar), two_rovs the linking number.
TEST(Runner, TopologyCsvHoldsTheFiveKindsAtTheOutputTimes)
{
  std::set<std::string> kinds;
  for (const char* name : {"pillar_wrap", "two_rovs"})
  {
    const std::string path = std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/" + name + ".yaml";
    Scenario scenario;
    ASSERT_EQ(loadScenario(path, &scenario), "");
    std::set<std::string> names;
    for (const auto& tether : scenario.tetherList())
    {
      names.insert(tether.name);
    }
    std::set<std::string> objects = names;
    for (const auto& obstacle : scenario.obstacles)
    {
      objects.insert(obstacle.name);
    }
    const std::string dir = temporaryDirectory(name);
    ASSERT_EQ(runRunner(path + " --out " + dir), 0);
    const auto rows = csvRows(fs::path(dir) / "topology.csv");
    ASSERT_GE(rows.size(), 2u) << name;
    EXPECT_EQ(readLines(fs::path(dir) / "topology.csv")[0], kTopologyCsvHeader);
    const auto outputs = static_cast<std::size_t>(std::floor(scenario.duration * scenario.output_rate + 1e-9));
    std::set<std::string> times;
    std::map<std::string, int> links;  // "t,tether,object" -> rows
    for (std::size_t r = 1; r < rows.size(); ++r)
    {
      const auto& row = rows[r];
      ASSERT_EQ(row.size(), 5u) << name << " row " << r;
      const double t = std::stod(row[0]);
      const double k = std::round(t * scenario.output_rate);
      EXPECT_LE(std::abs(t - k / scenario.output_rate), 5e-7) << row[0];  // printed with 6 decimals
      times.insert(row[0]);
      EXPECT_EQ(names.count(row[1]), 1u) << row[1];
      EXPECT_EQ(objects.count(row[2]), 1u) << row[2];
      EXPECT_TRUE(row[3] == "wrap_turns" || row[3] == "wrap_angle" || row[3] == "contact_angle" ||
                  row[3] == "linking_number" || row[3] == "capstan_ratio")
          << row[3];
      kinds.insert(row[3]);
      if (row[3] == "linking_number")
      {
        ++links[row[0] + "," + row[1] + "," + row[2]];
        EXPECT_EQ(row[1] + row[2], "ab");  // once per pair, the lower index first
      }
      if (row[3] == "wrap_turns" || row[3] == "wrap_angle")
      {
        EXPECT_EQ(row[2], "pillar");  // wraps are counted round obstacles with an axis only
      }
    }
    EXPECT_EQ(times.size(), outputs + 1) << name;  // rows at every output time
    for (const auto& [key, count] : links)
    {
      EXPECT_EQ(count, 1) << key;
    }
    fs::remove_all(dir);
  }
  EXPECT_EQ(kinds,
            (std::set<std::string>{"wrap_turns", "wrap_angle", "contact_angle", "linking_number", "capstan_ratio"}));
}

/// The value of the last row of `kind` for (tether, object) in topology.csv; NaN without one.
double lastTopologyValue(const fs::path& path, const std::string& tether, const std::string& object,
                         const std::string& kind)
{
  double value = std::nan("");
  for (const auto& row : csvRows(path))
  {
    if (row.size() == 5 && row[1] == tether && row[2] == object && row[3] == kind)
    {
      value = std::stod(row[4]);
    }
  }
  return value;
}

// The shipped world scenarios show what test_contact.cpp derives, through the runner and its files: the
// vehicle twice counter-clockwise round the pillar (seen from +z, the pillar's axis) leaves the tether, closed
// by its chord, wound +2 times round it; two vehicles turned once counter-clockwise about +x link their
// taut tethers once, +1. Winding and linking numbers of closed curves are integers; within 0.1, the issue's
// tolerance.
TEST(Runner, ShippedWorldScenariosWrapTwiceAndLinkOnce)
{
  const std::string dir = temporaryDirectory("shipped_world");
  ASSERT_EQ(runRunner(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/pillar_wrap.yaml --out " + dir), 0);
  EXPECT_NEAR(lastTopologyValue(fs::path(dir) / "topology.csv", "tether", "pillar", "wrap_turns"), 2.0, 0.1);
  fs::remove_all(dir);
  ASSERT_EQ(runRunner(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/two_rovs.yaml --out " + dir), 0);
  EXPECT_NEAR(lastTopologyValue(fs::path(dir) / "topology.csv", "a", "b", "linking_number"), 1.0, 0.1);
  fs::remove_all(dir);
}

// Two runs of a world's scenario with noise, from the same seed, write the same bytes in every file. The second
// spells its options with '=' (--out=DIR, --set=name=value), which the runner takes as the same options.
TEST(Runner, WorldRunsAreByteIdenticalFromTheSameSeed)
{
  const std::string dir = temporaryDirectory("seed");
  const fs::path scenario_path = fs::path(dir + "_scenario.yaml");
  std::ofstream(scenario_path) << kWorld;
  ASSERT_EQ(runRunner(scenario_path.string() + " --out " + dir + "/1 --set noise=0.002"), 0);
  ASSERT_EQ(runRunner(scenario_path.string() + " --out=" + dir + "/2 --set=noise=0.002"), 0);
  for (const char* file : {"a/state.csv", "a/shape.csv", "b/state.csv", "b/shape.csv", "topology.csv"})
  {
    const std::string first = fileText(fs::path(dir) / "1" / file);
    EXPECT_FALSE(first.empty()) << file;
    EXPECT_TRUE(first == fileText(fs::path(dir) / "2" / file)) << file << " differs between the runs";
  }
  // The seed matters: another one moves the noisy tethers (so the comparison above compares something).
  ASSERT_EQ(runRunner(scenario_path.string() + " --out " + dir + "/3 --set noise=0.002 --set seed=7"), 0);
  EXPECT_NE(fileText(fs::path(dir) / "1" / "a" / "shape.csv"), fileText(fs::path(dir) / "3" / "a" / "shape.csv"));
  fs::remove_all(dir);
  fs::remove(scenario_path);
}

}  // namespace
}  // namespace rov_tether::test

namespace rov_tether::test
{
namespace
{

// The physics core is ROS-free: no file of the core library includes a ROS header.
TEST(Layers, CoreIncludesNoRosHeader)
{
  int files = 0;
  for (const std::string folder : {"/src/core", "/include/rov_tether/core"})
  {
    for (const auto& entry : fs::directory_iterator(std::string(ROV_TETHER_SOURCE_DIR) + folder))
    {
      if (!entry.is_regular_file())
      {
        continue;
      }
      std::ifstream in(entry.path());
      for (std::string line; std::getline(in, line);)
      {
        if (line.rfind("#include", 0) == 0)
        {
          for (const char* ros : {"<ros/", "<tf2", "<geometry_msgs", "<visualization_msgs", "<std_msgs",
                                  "<dynamic_reconfigure", "<XmlRpc"})
          {
            EXPECT_EQ(line.find(ros), std::string::npos) << entry.path() << ": " << line;
          }
        }
      }
      ++files;
    }
  }
  EXPECT_GE(files, 8);
}

// The layers of docs/architecture.md: a header or source of one layer includes the package's headers of
// its own layer and of the layers below it only (core <- geometry, spec <- scenario <- camera, study; camera
// <- ros; the headers generated from msg/, srv/ and cfg/ in ros only),
// and no header of the package sits outside a layer's folder. A layer above would tie two libraries both
// ways (CMake links them one way); a flat header would hide which layer it belongs to.
TEST(Layers, NoFileIncludesALayerAboveIt)
{
  const std::map<std::string, std::set<std::string>> allowed = {
      {"core", {"core"}},
      {"geometry", {"core", "geometry"}},
      {"spec", {"core", "spec"}},
      {"scenario", {"core", "geometry", "spec", "scenario"}},
      {"camera", {"core", "geometry", "spec", "scenario", "camera"}},
      {"study", {"core", "geometry", "spec", "scenario", "study"}},
      {"ros", {"core", "geometry", "spec", "scenario", "camera", "ros", "generated"}},
  };
  const std::string root(ROV_TETHER_SOURCE_DIR);
  for (const auto& entry : fs::directory_iterator(root + "/include/rov_tether"))
  {
    EXPECT_TRUE(entry.is_directory()) << entry.path() << " sits in no layer's folder";
    EXPECT_EQ(allowed.count(entry.path().filename().string()), 1u) << entry.path() << " is no layer";
  }
  int includes = 0;
  for (const auto& [layer, below] : allowed)
  {
    for (const std::string& folder : {root + "/include/rov_tether/" + layer, root + "/src/" + layer})
    {
      ASSERT_TRUE(fs::is_directory(folder)) << folder;
      for (const auto& entry : fs::directory_iterator(folder))
      {
        std::ifstream in(entry.path());
        for (std::string line; std::getline(in, line);)
        {
          const std::string tag = "#include \"rov_tether/";
          if (line.rfind(tag, 0) != 0)
          {
            continue;
          }
          const std::string rest = line.substr(tag.size());
          // "rov_tether/X.h" with no folder: a header generated from msg/, srv/ or cfg/ (ROS only).
          const std::string included =
              rest.find('/') == std::string::npos ? "generated" : rest.substr(0, rest.find('/'));
          EXPECT_EQ(below.count(included), 1u) << entry.path() << " (" << layer << ") includes " << line;
          ++includes;
        }
      }
    }
  }
  EXPECT_GE(includes, 100);  // the scan found the package's includes (some 300 today), not an empty tree
}

// The scenario model, the CSV runner and the study need no YAML: only the reader (scenario_yaml) does.
TEST(Layers, OnlyTheScenarioReaderUsesYaml)
{
  for (const char* file :
       {"/src/scenario/scenario.cpp", "/src/scenario/scenario_runner.cpp", "/src/scenario/output_files.cpp",
        "/src/study/study.cpp", "/include/rov_tether/scenario/scenario.hpp",
        "/include/rov_tether/scenario/scenario_runner.hpp", "/include/rov_tether/study/study.hpp"})
  {
    std::ifstream in(std::string(ROV_TETHER_SOURCE_DIR) + file);
    ASSERT_TRUE(in) << file;
    for (std::string line; std::getline(in, line);)
    {
      if (line.rfind("#include", 0) == 0)
      {
        EXPECT_EQ(line.find("yaml"), std::string::npos) << file << ": " << line;
      }
    }
  }
}

}  // namespace
}  // namespace rov_tether::test
