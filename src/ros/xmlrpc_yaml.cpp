#include "rov_tether/ros/xmlrpc_yaml.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace rov_tether::ros_layer
{

YAML::Node toYaml(const XmlRpc::XmlRpcValue& value)
{
  auto& v = const_cast<XmlRpc::XmlRpcValue&>(value);  // XmlRpcValue's readers are not const
  switch (value.getType())
  {
    case XmlRpc::XmlRpcValue::TypeStruct:
    {
      YAML::Node map(YAML::NodeType::Map);
      for (const auto& member : v)
      {
        map[member.first] = toYaml(member.second);
      }
      return map;
    }
    case XmlRpc::XmlRpcValue::TypeArray:
    {
      YAML::Node list(YAML::NodeType::Sequence);
      for (int i = 0; i < value.size(); ++i)
      {
        list.push_back(toYaml(value[i]));
      }
      return list;
    }
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(v) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(std::to_string(static_cast<int>(v)));
    case XmlRpc::XmlRpcValue::TypeDouble:
    {
      const double number = static_cast<double>(v);
      if (!std::isfinite(number))  // YAML's spelling (.nan, .inf, -.inf), which yaml-cpp reads back
      {
        return YAML::Node(std::isnan(number) ? ".nan" : number > 0.0 ? ".inf" : "-.inf");
      }
      char text[32];
      std::snprintf(text, sizeof text, "%.17g", number);
      return YAML::Node(std::string(text));
    }
    case XmlRpc::XmlRpcValue::TypeString:
    {
      YAML::Node text(static_cast<std::string>(v));
      text.SetTag("!");
      return text;
    }
    default:
      return YAML::Node(YAML::NodeType::Null);
  }
}

}  // namespace rov_tether::ros_layer
