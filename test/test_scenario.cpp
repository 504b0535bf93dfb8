// Scenario files, parameter files and the rov_tether_run executable.
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

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
      {"params: {itrations: 3}\nspool: [0, 0, 0]\nduration: 1", "unknown parameter 'itrations'"},
      {"params: {bending: maybe}\nspool: [0, 0, 0]\nduration: 1", "parameter 'bending': wrong type"},
      {"params: {drag: [1]}\nspool: [0, 0, 0]\nduration: 1", "'drag': wrong type (a list), expected a number"},
      {"params: {current: [1, 2]}\nspool: [0, 0, 0]\nduration: 1", "'current': expected a list of 3 numbers"},
      {"params: {current: [1, a, 2]}\nspool: [0, 0, 0]\nduration: 1", "current: expected a list of numbers"},
      {"params: {segment_length: automatic}\nspool: [0, 0, 0]\nduration: 1", "'segment_length': wrong type"},
      {"params: 3\nspool: [0, 0, 0]\nduration: 1", "params.: expected a map"},
      {"spool: [0, 0, 0\nduration: 1", "YAML error"},
  };
  for (const auto& c : cases)
  {
    Scenario scenario;
    const std::string error = parseScenario(c.yaml, &scenario);
    EXPECT_NE(error.find(c.message), std::string::npos) << "yaml: " << c.yaml << "\nerror: " << error;
  }
}

// config/default.yaml holds every parameter at exactly the struct's default.
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
  fs::remove_all(dir);
  fs::remove(scenario_path);
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
  for (const std::string folder : {"/src/core", "/include/rov_tether"})
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

// The scenario model, the CSV runner and the study need no YAML: only the reader (scenario_yaml) does.
TEST(Layers, OnlyTheScenarioReaderUsesYaml)
{
  for (const char* file :
       {"/src/scenario/scenario.cpp", "/src/scenario/scenario_runner.cpp", "/src/study/study.cpp",
        "/include/rov_tether/scenario.hpp", "/include/rov_tether/scenario_runner.hpp", "/include/rov_tether/study.hpp"})
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
