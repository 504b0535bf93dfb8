// The parameter files generated from the one parameter table (parameterInfo()): config/default.yaml and
// cfg/Tether.cfg. scripts/generate_parameters.py writes them (rov_tether_run --parameters=yaml|cfg), and
// ParamTable.GeneratedFilesAreTheCommittedOnes fails when a committed file differs.
#include <algorithm>
#include <cmath>
#include <string>

#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{
namespace
{

/// The meaning without the README's markdown (backticks).
std::string plain(const std::string& text)
{
  std::string out;
  for (const char c : text)
  {
    if (c != '`')
    {
      out += c;
    }
  }
  return out;
}

/// A number as YAML 1.1 (PyYAML, so rosparam) reads it as a float: a dot, and a signed exponent.
std::string yamlFloat(const std::string& number)
{
  if (number == ".nan" || number.find_first_of("0123456789") == std::string::npos)
  {
    return number;
  }
  const auto e = number.find('e');
  std::string mantissa = number.substr(0, e);
  if (mantissa.find('.') == std::string::npos)
  {
    mantissa += ".0";
  }
  if (e == std::string::npos)
  {
    return mantissa;
  }
  const std::string exponent = number.substr(e + 1);
  return mantissa + "e" + (exponent[0] == '-' ? "" : "+") + exponent;
}

std::string yamlValue(const ParamValue& value)
{
  if (const auto* number = std::get_if<double>(&value))
  {
    return yamlFloat(formatParamValue(*number));
  }
  if (const auto* list = std::get_if<std::vector<double>>(&value))
  {
    std::string out = "[";
    for (const double v : *list)
    {
      out += (out.size() > 1 ? ", " : "") + yamlFloat(formatParamValue(v));
    }
    return out + "]";
  }
  return formatParamValue(value);
}

std::string joinedChoices(const std::string& name, const std::string& separator)
{
  std::string out;
  for (const ParameterChoice& choice : parameterChoices(name))
  {
    out += (out.empty() ? "" : separator) + choice.value;
  }
  return out;
}

/// A Python string literal.
std::string quoted(const std::string& text)
{
  std::string out = "\"";
  for (const char c : text)
  {
    out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  }
  return out + "\"";
}

}  // namespace

std::string defaultYaml()
{
  const TetherParams defaults;
  std::string out =
      "# rov_tether model parameters with their defaults (SI units). Every parameter is listed, with its unit and\n"
      "# meaning. Generated from the parameter table (parameterInfo() in src/core/parameter_table.cpp) by\n"
      "# scripts/generate_parameters.py: edit the table, not this file. The README's Parameters table gives ranges.\n";
  std::size_t width = 0;
  for (const ParameterInfo& info : parameterInfo())
  {
    width = std::max(width, info.name.size() + 2 + yamlValue(getParameter(defaults, info.name)).size());
  }
  for (const ParameterInfo& info : parameterInfo())
  {
    std::string line = info.name + ": " + yamlValue(getParameter(defaults, info.name));
    line.resize(width + 2, ' ');
    std::string comment = "[" + info.unit + "] " + plain(info.meaning);
    const std::string choices = joinedChoices(info.name, " | ");
    comment += choices.empty() ? "" : ": " + choices;
    comment += info.type.find("auto") != std::string::npos ? "; or auto" : "";
    out += line + "# " + comment + "\n";
  }
  return out;
}

std::string dynamicReconfigureCfg()
{
  const TetherParams defaults;
  std::string out =
      "#!/usr/bin/env python3\n"
      "\"\"\"Live parameters of tether_node (dynamic_reconfigure), generated from the parameter table\n"
      "(parameterInfo() in src/core/parameter_table.cpp) by scripts/generate_parameters.py: edit the table, not\n"
      "this file (ParamTable.GeneratedFilesAreTheCommittedOnes fails when they differ). dynamic_reconfigure runs\n"
      "this file when the package is configured, so it is committed. No range is given here: the server clamps a\n"
      "value to the .cfg's range before the node sees it, which would run an out-of-range request (iterations 0)\n"
      "silently as its bound. The node validates what was asked and refuses it whole with a WARN, and publishes\n"
      "the table's ranges (setConfigMin/Max) for rqt_reconfigure's sliders.\"\"\"\n"
      "from dynamic_reconfigure.parameter_generator_catkin import ParameterGenerator, bool_t, double_t, int_t, str_t\n"
      "\n"
      "PACKAGE = \"rov_tether\"\n"
      "gen = ParameterGenerator()\n"
      "\n";
  std::string adds;
  for (const ParameterInfo& info : parameterInfo())
  {
    if (!info.live)
    {
      continue;
    }
    const ParamValue value = getParameter(defaults, info.name);
    std::string type = "double_t";
    std::string shown = formatParamValue(value);
    std::string edit_method;
    switch (value.index())
    {
      case 0:
        type = "bool_t";
        shown = std::get<bool>(value) ? "True" : "False";
        break;
      case 1:
        type = "int_t";
        break;
      case 3:
      {
        type = "str_t";
        shown = quoted(shown);
        edit_method = info.name + "_choices";
        out += edit_method + " = gen.enum([";
        bool first = true;
        for (const ParameterChoice& choice : parameterChoices(info.name))
        {
          out += std::string(first ? "" : ",\n" + std::string(edit_method.size() + 13, ' ')) + "gen.const(" +
                 quoted(choice.value) + ", str_t, " + quoted(choice.value) + ", " + quoted(choice.meaning) + ")";
          first = false;
        }
        out += "],\n" + std::string(edit_method.size() + 12, ' ') + quoted(info.name) + ")\n";
        break;
      }
      default:
        break;
    }
    const std::string unit = type == "double_t" || type == "int_t" ? " [" + info.unit + "]" : "";
    adds += "gen.add(" + quoted(info.name) + ", " + type + ", 0, " + quoted(plain(info.meaning) + unit) + ", " + shown +
            (edit_method.empty() ? "" : ", edit_method=" + edit_method) + ")\n";
  }
  return out + "\n" + adds + "\nexit(gen.generate(PACKAGE, \"tether_node\", \"Tether\"))\n";
}

}  // namespace rov_tether
