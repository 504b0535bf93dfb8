#include "rov_tether/spec/yaml_read.hpp"

#include <cmath>

namespace rov_tether::spec
{

std::string readNumber(const YAML::Node& node, const std::string& field, double* value)
{
  if (!node.IsScalar() || node.Tag() == "!" || !YAML::convert<double>::decode(node, *value))
  {
    return field + ": expected a number";
  }
  if (!std::isfinite(*value))
  {
    return field + ": must be finite";
  }
  return "";
}

std::string readVector(const YAML::Node& node, const std::string& field, std::size_t size, double* values)
{
  if (!node.IsSequence() || node.size() != size)
  {
    return field + ": expected a list of " + std::to_string(size) + " numbers";
  }
  for (std::size_t i = 0; i < size; ++i)
  {
    const std::string error = readNumber(node[i], field + "[" + std::to_string(i) + "]", &values[i]);
    if (!error.empty())
    {
      return error;
    }
  }
  return "";
}

std::string readText(const YAML::Node& node, const std::string& field, std::string* value)
{
  // A plain scalar that reads as a number is a number (as the parameter server types it); quote it for text.
  double number = 0.0;
  if (!node.IsScalar() || node.Scalar().empty() || (node.Tag() != "!" && YAML::convert<double>::decode(node, number)))
  {
    return field + ": expected a string";
  }
  *value = node.Scalar();
  return "";
}

}  // namespace rov_tether::spec
