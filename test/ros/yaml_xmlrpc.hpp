#pragma once
// A YAML file as the parameter server would hold it (what `rosparam load` does), for tests without a master.

#include <XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace rov_tether::test
{

inline  /// A YAML file as the parameter server would hold it (what `rosparam load` does).
    XmlRpc::XmlRpcValue
    toXmlRpc(const YAML::Node& node)
{
  if (node.IsMap())
  {
    XmlRpc::XmlRpcValue result;
    for (const auto& entry : node)
    {
      result[entry.first.as<std::string>()] = toXmlRpc(entry.second);
    }
    return result;
  }
  if (node.IsSequence())
  {
    XmlRpc::XmlRpcValue result;
    result.setSize(static_cast<int>(node.size()));
    for (std::size_t i = 0; i < node.size(); ++i)
    {
      result[static_cast<int>(i)] = toXmlRpc(node[i]);
    }
    return result;
  }
  bool b;
  int i;
  double d;
  if (node.Tag() != "!" && YAML::convert<bool>::decode(node, b) &&
      node.Scalar().find_first_of("0123456789") == std::string::npos)
  {
    return XmlRpc::XmlRpcValue(b);
  }
  if (node.Tag() != "!" && YAML::convert<int>::decode(node, i))
  {
    return XmlRpc::XmlRpcValue(i);
  }
  if (node.Tag() != "!" && YAML::convert<double>::decode(node, d))
  {
    return XmlRpc::XmlRpcValue(d);
  }
  return XmlRpc::XmlRpcValue(node.Scalar());
}

inline XmlRpc::XmlRpcValue loadYaml(const std::string& relative)
{
  return toXmlRpc(YAML::LoadFile(std::string(ROV_TETHER_SOURCE_DIR) + "/" + relative));
}

}  // namespace rov_tether::test
