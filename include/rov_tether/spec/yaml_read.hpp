#pragma once
// Reading values out of a YAML node: the one description of a world is read from YAML (scenario files)
// or from the parameter server (converted to YAML first, ros/xmlrpc_yaml.hpp), by the same readers.

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <string>

namespace rov_tether::spec
{

/// Parses YAML text into `root` and refuses a key that a map holds twice (yaml-cpp keeps both and a lookup
/// takes the first; roslaunch and PyYAML keep the last): returns "" or "duplicate key 'path.key' (lines A and
/// B): give each key once" (or that the nesting is deeper than any file of ours, an alias naming its own
/// anchor; more than 1e7 values with aliases expanded; more than one YAML document). Throws YAML::Exception on
/// YAML that does not parse.
[[nodiscard]] std::string loadYamlText(const std::string& text, YAML::Node* root);

/// The file at `path` read as loadYamlText reads text: "" or the problem, prefixed with the path (a file that
/// cannot be read, YAML that does not parse, a repeated key). The node's check of the files its launch loaded.
[[nodiscard]] std::string checkYamlFile(const std::string& path);

/// Reads a finite number from a plain (unquoted) scalar; returns "" or "<field>: expected a number" /
/// "<field>: must be finite". A quoted scalar (tag "!", a string on the parameter server) is no number.
[[nodiscard]] std::string readNumber(const YAML::Node& node, const std::string& field, double* value);

/// Reads a list of exactly `size` numbers into `values`; returns "" or a message naming the field.
[[nodiscard]] std::string readVector(const YAML::Node& node, const std::string& field, std::size_t size,
                                     double* values);

/// Reads a non-empty string; returns "" or "<field>: expected a string". A plain scalar that reads as a number
/// is a number, not a string (as the parameter server types it): `name: 3` is refused, `name: '3'` taken.
[[nodiscard]] std::string readText(const YAML::Node& node, const std::string& field, std::string* value);

}  // namespace rov_tether::spec
