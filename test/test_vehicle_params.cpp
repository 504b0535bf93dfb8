// A vehicle's parameters (VehicleParams) and their one reader (spec::readVehicleParams): the shipped vehicle
// files load, and bad files are refused with a message naming the file and the field.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rov_tether/core/vehicle_params.hpp"
#include "rov_tether/spec/vehicle_reader.hpp"

namespace rov_tether::test
{
namespace
{

std::string vehicleFile(const std::string& name)
{
  return std::string(ROV_TETHER_SOURCE_DIR) + "/config/vehicles/" + name + ".yaml";
}

const char* const kComplete = R"(
mass: 13.5
displaced_volume: 0.0134
water_density: 1000.0
gravity: 9.81
inertia: [0.26, 0.23, 0.37]
center_of_gravity: [0.0, 0.0, 0.0]
center_of_buoyancy: [0.0, 0.0, 0.01]
added_mass: [6.36, 7.12, 18.68, 0.189, 0.135, 0.222]
linear_damping: [13.7, 0.0, 33.0, 0.0, 0.8, 0.0]
quadratic_damping: [141.0, 217.0, 190.0, 1.19, 0.47, 1.5]
thrust_limit: [113.7, 113.7, 160.8, 35.1, 19.3, 30.4]
size: [0.457, 0.575, 0.254]
)";

/// The complete text with the line of `field` replaced by `line` ("" drops it).
std::string withLine(const std::string& field, const std::string& line)
{
  std::string text = kComplete;
  const std::size_t at = text.find("\n" + field + ":");
  const std::size_t end = text.find('\n', at + 1);
  text.replace(at + 1, end - at, line.empty() ? "" : line + "\n");
  return text;
}

std::string readText(const std::string& text, VehicleParams* params)
{
  return spec::readVehicleParams(YAML::Load(text), "vehicles/test.yaml", params);
}

// The BlueROV2 Heavy file is VehicleParams' defaults, number for number (one description of the vehicle).
TEST(VehicleParams, ShippedBlueRov2FileIsTheDefaults)
{
  VehicleParams read;
  read.mass = 1.0;  // overwritten
  ASSERT_EQ(spec::loadVehicleParamsFile(vehicleFile("bluerov2_heavy"), &read), "");
  const VehicleParams defaults;
  EXPECT_EQ(read.mass, defaults.mass);
  EXPECT_EQ(read.displaced_volume, defaults.displaced_volume);
  EXPECT_EQ(read.water_density, defaults.water_density);
  EXPECT_EQ(read.gravity, defaults.gravity);
  EXPECT_EQ(read.inertia, defaults.inertia);
  EXPECT_EQ(read.center_of_gravity, defaults.center_of_gravity);
  EXPECT_EQ(read.center_of_buoyancy, defaults.center_of_buoyancy);
  EXPECT_EQ(read.added_mass, defaults.added_mass);
  EXPECT_EQ(read.linear_damping, defaults.linear_damping);
  EXPECT_EQ(read.quadratic_damping, defaults.quadratic_damping);
  EXPECT_EQ(read.thrust_limit, defaults.thrust_limit);
  EXPECT_EQ(read.size, defaults.size);
  EXPECT_TRUE(defaults.validate().ok) << defaults.validate().message;
}

// A vehicle file was read by YAML::Load alone: a key given twice was half-read (the first taken) and a second
// document after '---' never read, where a scenario's YAML refuses both. Now it is read as every YAML file is.
TEST(VehicleParams, AVehicleFileWithARepeatedKeyOrASecondDocumentIsRefused)
{
  std::ifstream shipped(vehicleFile("bluerov2_heavy"));
  std::stringstream text;
  text << shipped.rdbuf();
  const std::string path = (std::filesystem::temp_directory_path() / "rov_tether_vehicle_twice.yaml").string();
  for (const auto& [more, named] : std::vector<std::pair<std::string, std::string>>{
           {"mass: 500\n", "duplicate key 'mass'"}, {"---\nmass: 500\n", "2 YAML documents"}})
  {
    std::ofstream(path) << text.str() << more;
    VehicleParams read;
    const std::string error = spec::loadVehicleParamsFile(path, &read);
    EXPECT_NE(error.find(named), std::string::npos) << error;
  }
  std::ofstream(path) << text.str();
  VehicleParams read;
  EXPECT_EQ(spec::loadVehicleParamsFile(path, &read), "");
  std::filesystem::remove(path);
}

// The work-class example loads and is one (1-5 t), slightly light in the sea as such vehicles are trimmed.
TEST(VehicleParams, ShippedWorkClassExampleLoads)
{
  VehicleParams read;
  ASSERT_EQ(spec::loadVehicleParamsFile(vehicleFile("work_class_example"), &read), "");
  EXPECT_GE(read.mass, 1000.0);
  EXPECT_LE(read.mass, 5000.0);
  EXPECT_GT(read.buoyancy(), read.weight());
  EXPECT_LT(read.buoyancy() - read.weight(), 0.05 * read.weight());
}

// Refusals: each names the file and the field, and leaves the parameters as they were.
TEST(VehicleParams, BadFilesAreRefusedNamingFileAndField)
{
  VehicleParams params;
  ASSERT_EQ(readText(kComplete, &params), "");
  const VehicleParams before = params;
  struct Case
  {
    std::string text;
    std::string message;
  };
  const Case cases[] = {
      {withLine("mass", ""), "vehicles/test.yaml: mass: missing"},
      {withLine("mass", "mass: .nan"), "vehicles/test.yaml: mass: must be finite"},
      {withLine("mass", "mass: -13.5"), "vehicles/test.yaml: mass: must be > 0 kg (got -13.5)"},
      {withLine("mass", "mass: heavy"), "vehicles/test.yaml: mass: expected a number"},
      {withLine("mass", "mass: '13.5'"), "vehicles/test.yaml: mass: expected a number"},
      {withLine("displaced_volume", "displaced_volume: -0.01"),
       "vehicles/test.yaml: displaced_volume: must be >= 0 m^3 (got -0.01)"},
      {withLine("water_density", "water_density: 0"), "vehicles/test.yaml: water_density: must be > 0 kg/m^3 (got 0)"},
      {withLine("inertia", "inertia: [0.26, 0.23]"), "vehicles/test.yaml: inertia: expected a list of 3 numbers"},
      {withLine("inertia", "inertia: [0.26, -0.23, 0.37]"),
       "vehicles/test.yaml: inertia[1]: must be > 0 kg m^2 (got -0.23)"},
      {withLine("inertia", "inertia: [1.0, 0.23, 0.37]"),
       "vehicles/test.yaml: inertia: [1, 0.23, 0.37] is no rigid body's"},
      {withLine("added_mass", "added_mass: [6.36, 7.12, 18.68, 0.189, .inf, 0.222]"),
       "vehicles/test.yaml: added_mass[4]: must be finite"},
      {withLine("linear_damping", "linear_damping: [13.7, 0.0, -33.0, 0.0, 0.8, 0.0]"),
       "vehicles/test.yaml: linear_damping[2]: must be >= 0 (got -33)"},
      {withLine("thrust_limit", "thrust_limit: [113.7, 113.7, 160.8, 35.1, 19.3]"),
       "vehicles/test.yaml: thrust_limit: expected a list of 6 numbers"},
      {withLine("center_of_buoyancy", "center_of_buoyancy: [0.0, 0.0, 1000.0]"),
       "vehicles/test.yaml: center_of_buoyancy[2]: must be within +-100 m (got 1000)"},
      {std::string(kComplete) + "length: 0.46\n", "vehicles/test.yaml: length: no vehicle parameter of that name"},
      {withLine("size", ""), "vehicles/test.yaml: size: missing (expected a list of 3 numbers)"},
      {withLine("size", "size: [0.457, 0.0, 0.254]"), "vehicles/test.yaml: size[1]: must be > 0 m (got 0)"},
      {std::string(kComplete) + "mass: 14.0\n", "vehicles/test.yaml: mass: given twice"},
      {"[1, 2]", "vehicles/test.yaml: expected a map"},
      // Without a `controller:` block the gains are designed for the vehicle, and were not checked as a block's are:
      // 1e300 kg designs infinite gains, which the controller refused only when the run started (the runner aborted).
      {withLine("mass", "mass: 1.0e+300"), "vehicles/test.yaml: the controller designed for this vehicle: controller:"},
  };
  for (const auto& c : cases)
  {
    const std::string error = readText(c.text, &params);
    EXPECT_NE(error.find(c.message), std::string::npos) << "got: " << error << "\nexpected: " << c.message;
    EXPECT_EQ(params.mass, before.mass);
    EXPECT_EQ(params.inertia, before.inertia);
    EXPECT_EQ(params.thrust_limit, before.thrust_limit);
  }
  // Two problems at once: both named.
  const std::string both = readText(withLine("gravity", "") + "colour: red\n", &params);
  EXPECT_NE(both.find("gravity: missing"), std::string::npos) << both;
  EXPECT_NE(both.find("colour: no vehicle parameter"), std::string::npos) << both;
}

// A file that is not there, or no YAML, is refused naming its path.
TEST(VehicleParams, UnreadableFileIsRefusedNamingIt)
{
  VehicleParams params;
  const std::string missing = "/nonexistent/vehicle.yaml";
  EXPECT_EQ(spec::loadVehicleParamsFile(missing, &params), missing + ": cannot be read");
  const std::string path = ::testing::TempDir() + "vehicle_bad.yaml";
  {
    std::ofstream(path) << "mass: [1, 2\n";
  }
  const std::string error = spec::loadVehicleParamsFile(path, &params);
  EXPECT_EQ(error.rfind(path + ": YAML error", 0), 0u) << error;
  {
    std::ofstream(path) << withLine("mass", "mass: -1");
  }
  const std::string negative = spec::loadVehicleParamsFile(path, &params);
  EXPECT_EQ(negative, path + ": mass: must be > 0 kg (got -1)");
  std::remove(path.c_str());
  EXPECT_EQ(params.mass, VehicleParams().mass);
}

}  // namespace
}  // namespace rov_tether::test
