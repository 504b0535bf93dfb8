#include "rov_tether/spec/tether_reader.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

#include "rov_tether/core/status.hpp"
#include "rov_tether/spec/cable_material_reader.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::spec
{

std::string readParamValue(const YAML::Node& node, const std::string& prefix, const std::string& name,
                           ParamValue* value)
{
  if (node.IsSequence())
  {
    std::vector<double> list;
    for (const auto& item : node)
    {
      double number = 0.0;
      if (!item.IsScalar() || item.Tag() == "!" || !YAML::convert<double>::decode(item, number))
      {
        return prefix + name + ": expected a list of numbers";
      }
      list.push_back(number);
    }
    *value = list;
    return "";
  }
  if (!node.IsScalar())
  {
    return prefix + name + ": expected a single value or a list of numbers";
  }
  const std::string& text = node.Scalar();
  if (node.Tag() != "!")  // unquoted: may be a bool or a number
  {
    bool b = false;
    std::int64_t i = 0;
    double d = 0.0;
    if (YAML::convert<bool>::decode(node, b) && text.find_first_of("0123456789") == std::string::npos)
    {
      *value = b;
      return "";
    }
    if (YAML::convert<std::int64_t>::decode(node, i))
    {
      *value = i;
      return "";
    }
    if (YAML::convert<double>::decode(node, d))
    {
      *value = d;
      return "";
    }
  }
  *value = text;
  return "";
}

std::string readTetherParams(const YAML::Node& map, const std::string& prefix, ParamKeys keys, TetherParams* params,
                             std::vector<std::string>* warnings)
{
  // "params." names the map as "params" and a field in it as "params.drag".
  const std::string field_prefix = prefix.empty() || prefix.back() == '.' ? prefix : prefix + ".";
  if (!map.IsMap())
  {
    const std::string whole = prefix.empty() ? "parameters" : field_prefix.substr(0, field_prefix.size() - 1);
    return whole + ": expected a map of name: value";
  }
  const std::vector<std::string>& model = parameterNames();
  std::vector<std::string> errors;
  std::vector<std::pair<std::string, ParamValue>> values;
  TetherParams candidate = *params;
  for (const auto& entry : map)
  {
    const std::string name = entry.first.as<std::string>();
    // The cable's material along it: lists of maps, not in the parameter table.
    if (name == "sections" || name == "attachments")
    {
      const std::string error = name == "sections" ? readSections(entry.second, prefix, &candidate.sections)
                                                   : readAttachments(entry.second, prefix, &candidate.attachments);
      if (!error.empty())
      {
        errors.push_back(error);
      }
      continue;
    }
    if (keys == ParamKeys::kModelOnly && std::find(model.begin(), model.end(), name) == model.end())
    {
      continue;  // the caller's (a node option, `tethers`, ...)
    }
    ParamValue value;
    const std::string error = readParamValue(entry.second, prefix, name, &value);
    if (!error.empty())
    {
      errors.push_back(error);
      continue;
    }
    values.emplace_back(name, value);
  }
  // The core's one loader of parameter values: types and ranges, and the whole set validated.
  for (const auto& error : applyParameters(values, &candidate))
  {
    // The core's "parameter 'drag': ..." becomes "params.drag: ..." under a prefix, an unknown name ("unknown
    // parameter 'drg' (did you mean 'drag'?)") "params: unknown ...", and validate()'s ("drag = 2: ...")
    // "params.drag = 2: ...".
    const std::string quoted = "parameter '";
    const std::size_t end =
        error.compare(0, quoted.size(), quoted) == 0 ? error.find("':", quoted.size()) : std::string::npos;
    const bool unknown = error.rfind("unknown parameter", 0) == 0;
    errors.push_back(prefix.empty() ? error
                     : unknown      ? field_prefix.substr(0, field_prefix.size() - 1) + ": " + error
                     : end == std::string::npos
                         ? prefix + error
                         : field_prefix + error.substr(quoted.size(), end - quoted.size()) + error.substr(end + 1));
  }
  for (const auto& warning : parameterWarnings(values))
  {
    warnings->push_back(prefix + warning);
  }
  if (errors.empty())
  {
    *params = candidate;
  }
  return joinMessages(errors);
}

std::string readPosition(const YAML::Node& node, const std::string& field, Position* position)
{
  if (!node)
  {
    return field + ": missing (expected [x, y, z] in m)";
  }
  Position candidate;
  const std::string error = readVector(node, field, 3, candidate.data());
  if (!error.empty())
  {
    return error;
  }
  if (candidate.cwiseAbs().maxCoeff() > Tether::kMaxCoordinate)
  {
    return field + ": each coordinate must be within +-1e6 m";
  }
  *position = candidate;
  return "";
}

}  // namespace rov_tether::spec
