// One table of parameters (parameterInfo()): the README's table, config/default.yaml and cfg/Tether.cfg are
// generated from it (scripts/generate_parameters.py) and validate() takes its ranges. Each check fails on the
// first difference and names it; the semantic checks below test what the generated files say.
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

std::string sourceFile(const std::string& relative)
{
  std::ifstream in(std::string(ROV_TETHER_SOURCE_DIR) + "/" + relative);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

TEST(ParamTable, CoversEveryParameterInOrder)
{
  std::vector<std::string> names;
  for (const ParameterInfo& row : parameterInfo())
  {
    names.push_back(row.name);
  }
  EXPECT_EQ(names, parameterNames());
}

/// "" when `committed` is `generated`, else the first line that differs, both ways, and how to regenerate.
std::string firstDifference(const std::string& file, const std::string& committed, const std::string& generated)
{
  if (committed == generated)
  {
    return "";
  }
  std::istringstream got(committed), want(generated);
  std::string a, b;
  int line = 0;
  while (true)
  {
    ++line;
    const bool more_got = static_cast<bool>(std::getline(got, a));
    const bool more_want = static_cast<bool>(std::getline(want, b));
    if (!more_got || !more_want || a != b)
    {
      return file + " differs from what the parameter table generates, first at line " + std::to_string(line) +
             ":\n  committed: " + (more_got ? a : "(end)") + "\n  generated: " + (more_want ? b : "(end)") +
             "\n(or only in its last newline). Edit the table (src/core/parameter_table.cpp), not the file, and run "
             "/usr/bin/python3 scripts/generate_parameters.py";
    }
  }
}

// cfg/Tether.cfg, config/default.yaml and the README's table are the generated ones, byte for byte.
TEST(ParamTable, GeneratedFilesAreTheCommittedOnes)
{
  EXPECT_EQ(firstDifference("cfg/Tether.cfg", sourceFile("cfg/Tether.cfg"), dynamicReconfigureCfg()), "");
  EXPECT_EQ(firstDifference("config/default.yaml", sourceFile("config/default.yaml"), defaultYaml()), "");
  // dynamic_reconfigure runs the .cfg when the package is configured.
  EXPECT_EQ(access((std::string(ROV_TETHER_SOURCE_DIR) + "/cfg/Tether.cfg").c_str(), X_OK), 0)
      << "cfg/Tether.cfg is not executable (chmod +x; git keeps the mode)";
  // Only the table's lines of the README are generated: from "| name | type" to the next blank line.
  const std::string readme = sourceFile("README.md");
  const auto section = readme.find("## Parameters");
  ASSERT_NE(section, std::string::npos);
  const auto start = readme.find("| name | type", section);
  ASSERT_NE(start, std::string::npos);
  const auto end = readme.find("\n\n", start);
  EXPECT_EQ(
      firstDifference("README.md's parameter table", readme.substr(start, end - start + 1), parameterTableMarkdown()),
      "");
}

// default.yaml lists every parameter once, at its default, and nothing else.
TEST(ParamTable, DefaultYamlHoldsEveryDefault)
{
  const YAML::Node yaml = YAML::LoadFile(std::string(ROV_TETHER_SOURCE_DIR) + "/config/default.yaml");
  std::set<std::string> keys;
  for (const auto& entry : yaml)
  {
    keys.insert(entry.first.as<std::string>());
  }
  const std::vector<std::string>& names = parameterNames();
  EXPECT_EQ(keys, std::set<std::string>(names.begin(), names.end()));
  TetherParams loaded;
  loaded.cable_length = 123.0;  // anything but the default, so a missing key shows
  ASSERT_EQ(loadParamsFile(std::string(ROV_TETHER_SOURCE_DIR) + "/config/default.yaml", &loaded), "");
  const TetherParams defaults;
  for (const std::string& name : names)
  {
    EXPECT_TRUE(sameParamValue(getParameter(loaded, name), getParameter(defaults, name)))
        << name << ": default.yaml has " << formatParamValue(getParameter(loaded, name)) << ", the table "
        << formatParamValue(getParameter(defaults, name));
  }
}

// cfg/Tether.cfg: exactly the live parameters, each with the table's default and no range (the node checks
// every request itself), and the choices of each string parameter.
TEST(ParamTable, DynamicReconfigureAgreesWithTheTable)
{
  const std::string cfg = sourceFile("cfg/Tether.cfg");
  const std::regex add(
      R"re(gen\.add\("(\w+)",\s*(\w+),\s*\d+,\s*"[^"]*",\s*([^,\)]+)(?:,\s*([^,\)]+),\s*([^,\)]+))?)re");
  std::set<std::string> seen;
  const TetherParams defaults;
  for (std::sregex_iterator it(cfg.begin(), cfg.end(), add), end; it != end; ++it)
  {
    const std::string name = (*it)[1];
    const std::string type = (*it)[2];
    seen.insert(name);
    const ParameterInfo* row = nullptr;
    for (const ParameterInfo& candidate : parameterInfo())
    {
      row = candidate.name == name ? &candidate : row;
    }
    ASSERT_NE(row, nullptr) << name << " is in Tether.cfg but not in the table";
    EXPECT_TRUE(row->live) << name << " is in Tether.cfg but the table says it is not live";
    const ParamValue value = getParameter(defaults, name);
    const std::string shown = (*it)[3];
    if (type == "double_t" || type == "int_t")
    {
      const double number =
          value.index() == 1 ? static_cast<double>(std::get<std::int64_t>(value)) : std::get<double>(value);
      EXPECT_DOUBLE_EQ(std::stod(shown), number) << name << " default";
      // No range: dynamic_reconfigure's server clamps to the .cfg's range before the node sees a request,
      // so iterations 0 would run as 1 without a word. The node checks the request against the table and
      // publishes the table's ranges itself (configBounds, test Converters.ConfigBoundsAreTheTableRanges).
      EXPECT_FALSE((*it)[4].matched) << name << ": Tether.cfg gives a range; the server would clamp to it";
    }
    else if (type == "bool_t")
    {
      EXPECT_EQ(shown == "True", std::get<bool>(value)) << name << " default";
    }
    else
    {
      EXPECT_EQ(shown, "\"" + std::get<std::string>(value) + "\"") << name << " default";
      // The parameter's enum (edit_method=NAME) holds exactly the choices the table lists, and the core
      // accepts each of them.
      std::set<std::string> choices;
      for (const ParameterChoice& choice : parameterChoices(name))
      {
        choices.insert(choice.value);
      }
      ASSERT_FALSE(choices.empty()) << name << ": the table lists no choices";
      std::smatch method;
      const std::string line = (*it)[0].str() + cfg.substr(it->position() + it->length(), 200);
      ASSERT_TRUE(std::regex_search(line, method, std::regex(R"re(edit_method=(\w+))re"))) << name;
      std::smatch definition;
      ASSERT_TRUE(
          std::regex_search(cfg, definition, std::regex(method[1].str() + R"re(\s*=\s*gen\.enum\(\[([\s\S]*?)\])re")))
          << name << ": no enum " << method[1];
      std::set<std::string> constants;
      const std::string body = definition[1];
      const std::regex constant(R"re(gen\.const\("(\w+)")re");
      for (std::sregex_iterator c(body.begin(), body.end(), constant), e; c != e; ++c)
      {
        constants.insert((*c)[1]);
      }
      EXPECT_EQ(constants, choices) << name << ": Tether.cfg's enum differs from the table";
      for (const std::string& option : choices)
      {
        TetherParams p;
        EXPECT_EQ(setParameter(p, name, ParamValue(option)), "") << name << " = " << option;
      }
    }
  }
  for (const ParameterInfo& row : parameterInfo())
  {
    EXPECT_EQ(row.live, seen.count(row.name) == 1) << row.name << ": live in the table but not in Tether.cfg";
  }
}

// validate() takes every field's range from the table: a value just inside each bound passes, just
// outside fails, open bounds excluded.
TEST(ParamTable, ValidateUsesTheTableRanges)
{
  for (const ParameterInfo& row : parameterInfo())
  {
    if (std::isnan(row.min) || row.name == "seed")
    {
      continue;  // choices and flags; seed's 9e15 bound is below double spacing tests
    }
    const bool integer = row.type.rfind("int", 0) == 0;
    const double step = integer ? 1.0 : std::max(1e-9 * std::abs(row.max - row.min), 1e-15);
    auto errorsFor = [&](double value)
    {
      TetherParams p;
      // Loose relations so that only the field itself can fail.
      p.cable_length = row.name == "cable_length" ? value : 1e5;
      p.min_deployed_length = row.name == "min_deployed_length" ? value : 1e-3;
      p.initial_deployed_length = row.name == "initial_deployed_length" ? value : 1.0;
      p.segment_length = row.name == "segment_length" ? value : 1e-3;
      p.max_winch_speed = row.name == "max_winch_speed" ? value : 20.0;
      ParamValue v = integer ? ParamValue(static_cast<std::int64_t>(value)) : ParamValue(value);
      if (row.type == "double[3]")
      {
        v = std::vector<double>{value, 0.0, 0.0};
      }
      EXPECT_EQ(setParameter(p, row.name, v), "") << row.name;
      std::string joined;  // the field's own range errors only (relations are checked elsewhere)
      for (const std::string& e : p.validate())
      {
        joined += e.find("must be a finite number in") != std::string::npos ? e + "; " : "";
      }
      return joined;
    };
    const double inside_low = row.min_open ? row.min + step : row.min;
    const double inside_high = row.max_open ? row.max - step : row.max;
    EXPECT_EQ(errorsFor(inside_low).find(row.name), std::string::npos) << row.name << " = " << inside_low;
    EXPECT_EQ(errorsFor(inside_high).find(row.name), std::string::npos) << row.name << " = " << inside_high;
    const double outside_low = row.min_open ? row.min : row.min - step;
    const double outside_high = row.max_open ? row.max : row.max + step;
    EXPECT_NE(errorsFor(outside_low).find(row.name), std::string::npos) << row.name << " = " << outside_low;
    EXPECT_NE(errorsFor(outside_high).find(row.name), std::string::npos) << row.name << " = " << outside_high;
  }
}

// A value is written as the YAML that reads back as it (the node's messages quote asked values this way): a
// non-finite one as YAML's .nan, .inf and -.inf (an infinity was cast to an int exponent and printed as
// 1e-2147483648 in a helper's dynparam refusal), short exponents, a whole double with its ".0".
TEST(ParamTable, ValuesAreWrittenAsTheYamlThatReadsThem)
{
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(formatParamValue(ParamValue{inf}), ".inf");
  EXPECT_EQ(formatParamValue(ParamValue{-inf}), "-.inf");
  EXPECT_EQ(formatParamValue(ParamValue{std::nan("")}), ".nan");
  EXPECT_EQ(formatParamValue(ParamValue{1e-8}), "1e-8");
  EXPECT_EQ(formatParamValue(ParamValue{2.0}), "2.0");
  EXPECT_EQ(formatParamValue(ParamValue{std::vector<double>{inf, 0.5}}), "[.inf, 0.5]");
}

}  // namespace
}  // namespace rov_tether::test
