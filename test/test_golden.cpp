// Golden outputs of the scenario runner: every shipped scenario, as shipped and under variants that reach
// each method, drag model, winch mode and input path, must write byte-identical state.csv and shape.csv
// (the scenarios of a world, with obstacles or several tethers, and those with a dynamic vehicle, as shipped:
// every file they write). The hashes live in test/golden/runner.txt, runner_worlds.txt and runner_vehicles.txt
// (see golden.hpp for how to regenerate them on purpose).
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "golden.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"

namespace rov_tether::test
{
namespace
{

/// Parameter overrides applied like the runner's --set; each reaches code the shipped files may not.
const std::vector<std::pair<std::string, std::vector<std::string>>>& variants()
{
  static const std::vector<std::pair<std::string, std::vector<std::string>>> list = {
      {"shipped", {}},
      {"xpbd_bending", {"solver=xpbd", "bending_stiffness=0.02", "substeps=2"}},
      {"lumped_mass", {"solver=lumped_mass", "iterations=auto"}},
      {"sequential", {"solver=pbd_sequential", "iterations=4"}},
      {"morison_seabed",
       {"drag_model=morison", "weight_in_water=0.5", "current=[0.1, -0.2, 0.0]", "current_variation=0.05",
        "seabed_z=-2.0", "seabed_friction=0.3", "noise=0.001"}},
      {"speed_winch", {"winch_mode=speed", "winch_speed=0.3", "over_relaxation=1.5", "drag=0.8"}},
      {"auto_resolution", {"segment_length=auto", "iterations=auto", "weight_in_water=0.2", "max_vehicle_jump=0.2"}},
  };
  return list;
}

/// The shipped scenarios/*.yaml, sorted.
std::vector<std::filesystem::path> shippedScenarioFiles()
{
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios"))
  {
    if (entry.path().extension() == ".yaml")
    {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// One test per variant (the suite's shards then share them out: under the sanitizers the seven took a
/// quarter of an hour in one test); all of them own test/golden/runner.txt's keys "scenario/variant/file".
class GoldenVariant : public ::testing::TestWithParam<std::size_t>
{
};

std::string variantName(const ::testing::TestParamInfo<std::size_t>& info) { return variants()[info.param].first; }

INSTANTIATE_TEST_SUITE_P(Golden, GoldenVariant, ::testing::Range<std::size_t>(0, variants().size()), variantName);

TEST_P(GoldenVariant, RunnerOutputsOfEveryShippedScenario)
{
  namespace fs = std::filesystem;
  const auto& [variant, assignments] = variants()[GetParam()];
  GoldenFile golden("runner.txt", "/" + variant + "/");
  const std::vector<fs::path> files = shippedScenarioFiles();
  ASSERT_GE(files.size(), 5u);
  const fs::path out = fs::temp_directory_path() / ("rov_tether_golden_" + variant + "_" + std::to_string(::getpid()));
  std::size_t cases = 0;
  std::size_t worlds = 0;
  std::size_t dynamic = 0;
  for (const auto& file : files)
  {
    Scenario shipped;
    ASSERT_EQ(loadScenario(file.string(), &shipped), "") << file;
    if (shipped.hasDynamicVehicle())
    {
      ++dynamic;
      continue;  // a dynamic vehicle (dynamic_dive, pillar_wrap_dynamic, tms): as shipped only, below
    }
    if (shipped.usesWorld())
    {
      // Obstacles or several tethers (pillar_wrap, two_rovs): as shipped only, in the test below (the
      // variants' --set would apply to the top-level params, which a `tethers` list does not use).
      ++worlds;
      continue;
    }
    Scenario scenario;
    ASSERT_EQ(loadScenario(file.string(), &scenario), "") << file;
    std::string error;
    for (const auto& assignment : assignments)
    {
      error += applyAssignment(assignment, &scenario.params);
    }
    if (!error.empty())
    {
      continue;  // a variant the scenario's own parameters contradict (e.g. a locked winch's lengths)
    }
    const std::string key = file.stem().string() + "/" + variant;
    RunSummary summary;
    ASSERT_EQ(runScenario(scenario, out.string(), &summary), "") << key;
    golden.check(key + "/state.csv", fnv1a(readFile((out / "state.csv").string())));
    golden.check(key + "/shape.csv", fnv1a(readFile((out / "shape.csv").string())));
    ++cases;
  }
  fs::remove_all(out);
  golden.expectAllChecked();
  // Every scenario takes every variant today: a variant that stops applying is a change to look at.
  EXPECT_EQ(cases, files.size() - worlds - dynamic);
  EXPECT_EQ(worlds, 2u);  // pillar_wrap.yaml and two_rovs.yaml; a plain scenario that became a world's would show
}

// runner.txt holds no key that no variant's case owns: a variant removed or renamed would leave its hashes
// behind unchecked (each GoldenVariant case checks only its own keys). Fails with a key of another name added.
TEST(Golden, EveryRunnerHashBelongsToAVariant)
{
  std::istringstream in(readFile(std::string(ROV_TETHER_SOURCE_DIR) + "/test/golden/runner.txt"));
  std::string key, value;
  std::size_t keys = 0;
  while (in >> key >> value)
  {
    ++keys;
    const bool owned =
        std::any_of(variants().begin(), variants().end(),
                    [&](const auto& variant) { return key.find("/" + variant.first + "/") != std::string::npos; });
    EXPECT_TRUE(owned) << key << " in test/golden/runner.txt belongs to no variant of test_golden.cpp";
  }
  EXPECT_GT(keys, 0u);
}

/// Runs each shipped scenario that `wanted` picks, as shipped, and checks the hash of every file it writes in
/// `golden` under "scenario/relative path"; returns how many ran.
template <typename Wanted>
std::size_t checkEveryFileAsShipped(GoldenFile& golden, const std::string& tag, Wanted wanted)
{
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("rov_tether_golden_" + tag + "_" + std::to_string(::getpid()));
  std::size_t ran = 0;
  for (const auto& file : shippedScenarioFiles())
  {
    Scenario scenario;
    const std::string loaded = loadScenario(file.string(), &scenario);
    if (!loaded.empty())
    {
      ADD_FAILURE() << file << ": " << loaded;
      continue;
    }
    if (!wanted(scenario))
    {
      continue;
    }
    fs::remove_all(out);
    RunSummary summary;
    const std::string run = runScenario(scenario, out.string(), &summary);
    if (!run.empty())
    {
      ADD_FAILURE() << file << ": " << run;  // its hashes are then missing, which expectAllChecked says too
      continue;
    }
    std::vector<fs::path> written;
    for (const auto& entry : fs::recursive_directory_iterator(out))
    {
      if (entry.is_regular_file())
      {
        written.push_back(fs::relative(entry.path(), out));
      }
    }
    std::sort(written.begin(), written.end());
    EXPECT_GE(written.size(), 3u) << file << ": at least a tether's state and shape, and one more";
    for (const auto& relative : written)
    {
      golden.check(file.stem().string() + "/" + relative.generic_string(), fnv1a(readFile((out / relative).string())));
    }
    ++ran;
  }
  fs::remove_all(out);
  golden.expectAllChecked();
  return ran;
}

// The shipped scenarios of a world (obstacles, several tethers, contact between them): as shipped, every
// file the runner writes (each tether's state.csv and shape.csv, and topology.csv) is byte-identical.
TEST(Golden, RunnerOutputsOfTheShippedWorlds)
{
  GoldenFile golden("runner_worlds.txt");
  const std::size_t worlds = checkEveryFileAsShipped(
      golden, "worlds", [](const Scenario& scenario) { return scenario.usesWorld() && !scenario.hasDynamicVehicle(); });
  EXPECT_EQ(worlds, 2u);  // pillar_wrap.yaml and two_rovs.yaml
}

// The shipped scenarios with a dynamic vehicle (a body in the water, its thrust from a schedule or its
// controller, the tether's pull coupled into its step): as shipped, every file the runner writes (the
// tethers' state.csv and shape.csv, each vehicle's vehicle.csv, topology.csv of a world) is byte-identical.
// The variants above leave them out (their --set would not reach a `tethers` list's parameters, and a
// vehicle's thrust limits and controller are tuned to the shipped cable).
TEST(Golden, RunnerOutputsOfTheShippedDynamicVehicles)
{
  GoldenFile golden("runner_vehicles.txt");
  const std::size_t runs = checkEveryFileAsShipped(
      golden, "vehicles", [](const Scenario& scenario) { return scenario.hasDynamicVehicle(); });
  EXPECT_EQ(runs, 3u);  // dynamic_dive.yaml, pillar_wrap_dynamic.yaml and tms.yaml
}

}  // namespace
}  // namespace rov_tether::test
