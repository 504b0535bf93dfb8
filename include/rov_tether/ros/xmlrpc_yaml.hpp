#pragma once
// The parameter server's values as YAML, so the node reads a world's description with the same readers
// (spec::) as the scenario runner reads its files.

#include <XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

namespace rov_tether::ros_layer
{

/// `value` as a YAML node: a struct as a map, an array as a sequence, a number or a boolean as a plain
/// scalar (a double to 17 significant digits: it reads back the same), a string as a quoted scalar (tag
/// "!": never taken for a number), anything else (date, binary, unset) as a null node.
YAML::Node toYaml(const XmlRpc::XmlRpcValue& value);

}  // namespace rov_tether::ros_layer
