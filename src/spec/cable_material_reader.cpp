#include "rov_tether/spec/cable_material_reader.hpp"

#include <algorithm>
#include <utility>

#include "rov_tether/core/status.hpp"
#include "rov_tether/spec/yaml_read.hpp"

namespace rov_tether::spec
{
namespace
{

/// Each item of a list of maps, or the one error that it is not one.
template <typename ReadItem>
std::string readList(const YAML::Node& node, const std::string& field, const char* what, ReadItem read_item)
{
  if (!node.IsSequence())
  {
    return field + ": expected a list of maps (" + what + ")";
  }
  std::vector<std::string> errors;
  for (std::size_t k = 0; k < node.size(); ++k)
  {
    const std::string item = field + "[" + std::to_string(k) + "]";
    if (!node[k].IsMap())
    {
      errors.push_back(item + ": expected a map (" + what + ")");
      continue;
    }
    read_item(node[k], item, &errors);
  }
  return joinMessages(errors);
}

}  // namespace

std::string readSections(const YAML::Node& node, const std::string& prefix, std::vector<CableSection>* sections)
{
  std::vector<CableSection> read;
  const std::string error =
      readList(node, prefix + "sections", "length and per-metre parameters",
               [&](const YAML::Node& map, const std::string& item, std::vector<std::string>* errors)
               {
                 CableSection section;
                 for (const auto& entry : map)
                 {
                   const std::string key = entry.first.as<std::string>();
                   double value = 0.0;
                   const std::string bad = readNumber(entry.second, item + "." + key, &value);
                   if (!bad.empty())
                   {
                     errors->push_back(bad);
                   }
                   else if (key == "length")
                   {
                     section.length = value;
                   }
                   else
                   {
                     section.properties.emplace_back(key, value);
                   }
                 }
                 read.push_back(std::move(section));
               });
  if (error.empty())
  {
    *sections = std::move(read);
  }
  return error;
}

std::string readAttachments(const YAML::Node& node, const std::string& prefix,
                            std::vector<CableAttachment>* attachments)
{
  std::vector<CableAttachment> read;
  const std::string error =
      readList(node, prefix + "attachments", "name, arc_length_from_vehicle, mass, net_buoyancy, ...",
               [&](const YAML::Node& map, const std::string& item, std::vector<std::string>* errors)
               {
                 CableAttachment attachment;
                 const std::vector<std::pair<const char*, double*>> numbers = {
                     {"arc_length_from_vehicle", &attachment.arc_length_from_vehicle},
                     {"mass", &attachment.mass},
                     {"net_buoyancy", &attachment.net_buoyancy},
                     {"added_mass", &attachment.added_mass},
                     {"drag_area", &attachment.drag_area},
                     {"drag_coefficient", &attachment.drag_coefficient}};
                 for (const auto& entry : map)
                 {
                   const std::string key = entry.first.as<std::string>();
                   const auto field = std::find_if(numbers.begin(), numbers.end(),
                                                   [&](const auto& number) { return key == number.first; });
                   std::string bad;
                   if (key == "name")
                   {
                     bad = readText(entry.second, item + ".name", &attachment.name);
                   }
                   else if (field != numbers.end())
                   {
                     bad = readNumber(entry.second, item + "." + key, field->second);
                   }
                   else
                   {
                     bad = item + "." + key +
                           ": unknown key (name, arc_length_from_vehicle, mass, net_buoyancy, added_mass, "
                           "drag_area, drag_coefficient)";
                   }
                   if (!bad.empty())
                   {
                     errors->push_back(bad);
                   }
                 }
                 for (const char* required : {"name", "arc_length_from_vehicle"})
                 {
                   if (!map[required])
                   {
                     errors->push_back(item + "." + required + ": missing");
                   }
                 }
                 read.push_back(std::move(attachment));
               });
  if (error.empty())
  {
    *attachments = std::move(read);
  }
  return error;
}

}  // namespace rov_tether::spec
