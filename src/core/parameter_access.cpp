#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <utility>

#include "parameter_members.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{
namespace members
{

const std::vector<std::pair<std::string, Member>>& parameterTable()
{
  static const std::vector<std::pair<std::string, Member>> table = {
      {"cable_length", &TetherParams::cable_length},
      {"segment_length", &TetherParams::segment_length},
      {"shape_tolerance", &TetherParams::shape_tolerance},
      {"min_bend_radius", &TetherParams::min_bend_radius},
      {"initial_deployed_length", &TetherParams::initial_deployed_length},
      {"time_step", &TetherParams::time_step},
      {"solver", &TetherParams::solver},
      {"substeps", &TetherParams::substeps},
      {"iterations", &TetherParams::iterations},
      {"over_relaxation", &TetherParams::over_relaxation},
      {"solver_tolerance", &TetherParams::solver_tolerance},
      {"stretch_tolerance", &TetherParams::stretch_tolerance},
      {"bending", &TetherParams::bending},
      {"drag", &TetherParams::drag},
      {"noise", &TetherParams::noise},
      {"seed", &TetherParams::seed},
      {"weight_in_water", &TetherParams::weight_in_water},
      {"mass_per_length", &TetherParams::mass_per_length},
      {"axial_stiffness", &TetherParams::axial_stiffness},
      {"axial_damping", &TetherParams::axial_damping},
      {"bending_stiffness", &TetherParams::bending_stiffness},
      {"drag_model", &TetherParams::drag_model},
      {"diameter", &TetherParams::diameter},
      {"water_density", &TetherParams::water_density},
      {"normal_drag_coefficient", &TetherParams::normal_drag_coefficient},
      {"tangential_drag_coefficient", &TetherParams::tangential_drag_coefficient},
      {"added_mass_coefficient", &TetherParams::added_mass_coefficient},
      {"current", &TetherParams::current},
      {"current_variation", &TetherParams::current_variation},
      {"seabed_z", &TetherParams::seabed_z},
      {"water_surface_z", &TetherParams::water_surface_z},
      {"seabed_friction", &TetherParams::seabed_friction},
      {"cable_friction", &TetherParams::cable_friction},
      {"winch_mode", &TetherParams::winch_mode},
      {"brake_tension", &TetherParams::brake_tension},
      {"winch_inertia", &TetherParams::winch_inertia},
      {"target_tension", &TetherParams::target_tension},
      {"tension_deadband", &TetherParams::tension_deadband},
      {"winch_speed", &TetherParams::winch_speed},
      {"max_winch_speed", &TetherParams::max_winch_speed},
      {"max_winch_acceleration", &TetherParams::max_winch_acceleration},
      {"max_winch_pull", &TetherParams::max_winch_pull},
      {"payout_threshold", &TetherParams::payout_threshold},
      {"reel_in_slack", &TetherParams::reel_in_slack},
      {"min_deployed_length", &TetherParams::min_deployed_length},
      {"max_vehicle_jump", &TetherParams::max_vehicle_jump},
      {"max_vehicle_speed", &TetherParams::max_vehicle_speed},
  };
  return table;
}

const Member* findMember(const std::string& name)
{
  for (const auto& entry : parameterTable())
  {
    if (entry.first == name)
    {
      return &entry.second;
    }
  }
  return nullptr;
}

}  // namespace members

namespace
{

using members::findMember;
using members::Member;
using members::parameterTable;
using members::Vector3;

/// Parameters that also accept the string "auto", with the flag it sets.
bool TetherParams::*autoFlag(const std::string& name)
{
  if (name == "segment_length")
  {
    return &TetherParams::segment_length_auto;
  }
  if (name == "iterations")
  {
    return &TetherParams::iterations_auto;
  }
  return nullptr;
}

std::string typeName(const ParamValue& value)
{
  switch (value.index())
  {
    case 0:
      return "a boolean";
    case 1:
      return "an integer";
    case 2:
      return "a number";
    case 3:
      return "a string";
    default:
      return "a list";
  }
}

/// Sets a number field from a number or an integer; "" or the wrong-type message.
std::string assignField(double& target, const ParamValue& value, const std::string& /*name*/,
                        const std::string& wrong_type)
{
  if (const auto* d = std::get_if<double>(&value))
  {
    target = *d;
    return "";
  }
  if (const auto* i = std::get_if<std::int64_t>(&value))
  {
    target = static_cast<double>(*i);
    return "";
  }
  const auto* text = std::get_if<std::string>(&value);
  std::string word = text != nullptr ? *text : "";
  std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::tolower(c); });
  const bool non_finite = word == "nan" || word == "inf" || word == "-inf" || word == "infinity";
  // YAML reads nan and inf as text: its own words for them are .nan, .inf and -.inf (then refused as not finite
  // where a parameter must be).
  return wrong_type + "a number" + (non_finite ? " (YAML writes NaN and infinity as .nan, .inf and -.inf)" : "");
}

/// Sets an integer field from an integer or a whole number, within the field's range.
template <typename Field>
std::string assignInteger(Field& target, const ParamValue& value, const std::string& name,
                          const std::string& wrong_type)
{
  std::int64_t integer = 0;
  if (const auto* i = std::get_if<std::int64_t>(&value))
  {
    integer = *i;
  }
  else if (const auto* d = std::get_if<double>(&value);
           d != nullptr && std::isfinite(*d) && std::floor(*d) == *d && std::abs(*d) < 9.0e15)
  {
    integer = static_cast<std::int64_t>(*d);
  }
  else
  {
    return wrong_type + "an integer";
  }
  if (integer < std::numeric_limits<Field>::min() || integer > std::numeric_limits<Field>::max())
  {
    return "parameter '" + name + "' = " + std::to_string(integer) + ": out of the integer range";
  }
  target = static_cast<Field>(integer);
  return "";
}

/// Sets an int field (assignInteger).
std::string assignField(int& target, const ParamValue& value, const std::string& name, const std::string& wrong_type)
{
  return assignInteger(target, value, name, wrong_type);
}

/// Sets a 64-bit integer field (assignInteger).
std::string assignField(std::int64_t& target, const ParamValue& value, const std::string& name,
                        const std::string& wrong_type)
{
  return assignInteger(target, value, name, wrong_type);
}

/// Sets a flag from true or false.
std::string assignField(bool& target, const ParamValue& value, const std::string& /*name*/,
                        const std::string& wrong_type)
{
  if (const auto* b = std::get_if<bool>(&value))
  {
    target = *b;
    return "";
  }
  return wrong_type + "true or false";
}

/// Sets the solver from its name.
std::string assignField(SolverType& target, const ParamValue& value, const std::string& /*name*/,
                        const std::string& /*wrong_type*/)
{
  const auto* s = std::get_if<std::string>(&value);
  if (s == nullptr || !parseSolver(*s, &target))
  {
    return "parameter 'solver': expected one of pbd, pbd_sequential, xpbd, lumped_mass, direct";
  }
  return "";
}

/// Sets the drag model from its name.
std::string assignField(DragModel& target, const ParamValue& value, const std::string& /*name*/,
                        const std::string& /*wrong_type*/)
{
  const auto* s = std::get_if<std::string>(&value);
  if (s == nullptr || !parseDragModel(*s, &target))
  {
    return "parameter 'drag_model': expected one of damping, morison";
  }
  return "";
}

/// Sets a vector field from a list of three numbers.
std::string assignField(Vector3& target, const ParamValue& value, const std::string& name,
                        const std::string& /*wrong_type*/)
{
  const auto* v = std::get_if<std::vector<double>>(&value);
  if (v == nullptr || v->size() != 3)
  {
    return "parameter '" + name + "': expected a list of 3 numbers [x, y, z]";
  }
  std::copy(v->begin(), v->end(), target.begin());
  return "";
}

/// Sets the winch mode from its name.
std::string assignField(WinchMode& target, const ParamValue& value, const std::string& /*name*/,
                        const std::string& /*wrong_type*/)
{
  const auto* s = std::get_if<std::string>(&value);
  if (s == nullptr || !parseWinchMode(*s, &target))
  {
    return "parameter 'winch_mode': expected one of brake, constant_tension, speed, locked, strain";
  }
  return "";
}

}  // namespace

const std::vector<std::string>& parameterNames()
{
  static const std::vector<std::string> names = []
  {
    std::vector<std::string> result;
    for (const auto& entry : parameterTable())
    {
      result.push_back(entry.first);
    }
    return result;
  }();
  return names;
}

std::string closestName(const std::string& name, const std::vector<std::string>& candidates)
{
  const std::size_t limit = name.size() < 6 ? 1 : 2;
  std::string best;
  std::size_t best_distance = limit + 1;
  bool tie = false;
  std::vector<std::size_t> row(name.size() + 1), next(name.size() + 1);
  for (const std::string& candidate : candidates)
  {
    // Levenshtein distance, one row at a time.
    for (std::size_t i = 0; i <= name.size(); ++i)
    {
      row[i] = i;
    }
    for (std::size_t j = 1; j <= candidate.size(); ++j)
    {
      next[0] = j;
      for (std::size_t i = 1; i <= name.size(); ++i)
      {
        const std::size_t substitute = row[i - 1] + (name[i - 1] == candidate[j - 1] ? 0 : 1);
        next[i] = std::min({row[i] + 1, next[i - 1] + 1, substitute});
      }
      std::swap(row, next);
    }
    const std::size_t distance = row[name.size()];
    if (distance < best_distance)
    {
      best = candidate, best_distance = distance, tie = false;
    }
    else if (distance == best_distance)
    {
      tie = true;
    }
  }
  return best_distance <= limit && !tie ? best : "";
}

std::string setParameter(TetherParams& params, const std::string& name, const ParamValue& value)
{
  const Member* member = findMember(name);
  if (member == nullptr)
  {
    const std::string guess = closestName(name, parameterNames());
    return "unknown parameter '" + name + "'" + (guess.empty() ? "" : " (did you mean '" + guess + "'?)");
  }
  if (bool TetherParams::*flag = autoFlag(name))
  {
    const auto* text = std::get_if<std::string>(&value);
    params.*flag = text != nullptr && *text == "auto";
    if (params.*flag)
    {
      return "";
    }
  }
  const std::string wrong_type = "parameter '" + name + "': wrong type (" + typeName(value) + "), expected ";
  return std::visit([&](auto field) { return assignField(params.*field, value, name, wrong_type); }, *member);
}

std::vector<std::string> applyParameters(const std::vector<std::pair<std::string, ParamValue>>& values,
                                         TetherParams* params)
{
  TetherParams candidate = *params;
  std::vector<std::string> errors;
  for (const auto& [name, value] : values)
  {
    const std::string error = setParameter(candidate, name, value);
    if (!error.empty())
    {
      errors.push_back(error);
    }
  }
  if (errors.empty())
  {
    errors = candidate.validate();
  }
  if (errors.empty())
  {
    *params = candidate;
  }
  return errors;
}

ParamValue getParameter(const TetherParams& params, const std::string& name)
{
  const Member* member = findMember(name);
  if (member == nullptr)
  {
    throw std::out_of_range("unknown parameter '" + name + "'");
  }
  if (bool TetherParams::*flag = autoFlag(name); flag != nullptr && params.*flag)
  {
    return std::string("auto");
  }
  return std::visit(
      [&](auto field) -> ParamValue
      {
        const auto& value = params.*field;
        using Field = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<Field, int> || std::is_same_v<Field, std::int64_t>)
        {
          return static_cast<std::int64_t>(value);
        }
        else if constexpr (std::is_same_v<Field, SolverType> || std::is_same_v<Field, WinchMode> ||
                           std::is_same_v<Field, DragModel>)
        {
          return toString(value);
        }
        else if constexpr (std::is_same_v<Field, Vector3>)
        {
          return std::vector<double>(value.begin(), value.end());
        }
        else
        {
          return value;
        }
      },
      *member);
}

std::string toString(SolverType solver)
{
  switch (solver)
  {
    case SolverType::kPbd:
      return "pbd";
    case SolverType::kPbdSequential:
      return "pbd_sequential";
    case SolverType::kXpbd:
      return "xpbd";
    case SolverType::kDirect:
      return "direct";
    default:
      return "lumped_mass";
  }
}

std::string toString(DragModel model) { return model == DragModel::kDamping ? "damping" : "morison"; }

bool parseDragModel(const std::string& text, DragModel* model)
{
  for (DragModel candidate : {DragModel::kDamping, DragModel::kMorison})
  {
    if (text == toString(candidate))
    {
      *model = candidate;
      return true;
    }
  }
  return false;
}

std::string toString(WinchMode mode)
{
  switch (mode)
  {
    case WinchMode::kBrake:
      return "brake";
    case WinchMode::kConstantTension:
      return "constant_tension";
    case WinchMode::kLocked:
      return "locked";
    case WinchMode::kStrain:
      return "strain";
    default:
      return "speed";
  }
}

bool parseSolver(const std::string& text, SolverType* solver)
{
  for (SolverType candidate :
       {SolverType::kPbd, SolverType::kPbdSequential, SolverType::kXpbd, SolverType::kLumpedMass, SolverType::kDirect})
  {
    if (text == toString(candidate))
    {
      *solver = candidate;
      return true;
    }
  }
  return false;
}

bool parseWinchMode(const std::string& text, WinchMode* mode)
{
  for (WinchMode candidate :
       {WinchMode::kBrake, WinchMode::kConstantTension, WinchMode::kSpeed, WinchMode::kLocked, WinchMode::kStrain})
  {
    if (text == toString(candidate))
    {
      *mode = candidate;
      return true;
    }
  }
  if (text == "passive")
  {
    *mode = WinchMode::kStrain;
    return true;
  }
  return false;
}

std::vector<std::string> parameterWarnings(const std::vector<std::pair<std::string, ParamValue>>& values)
{
  std::vector<std::string> warnings;
  for (const auto& [name, value] : values)
  {
    const auto* text = std::get_if<std::string>(&value);
    if (name == "winch_mode" && text != nullptr && *text == "passive")
    {
      warnings.push_back(
          "winch_mode 'passive' is deprecated: it is now 'strain' (the paper's rule, pay-out when the first "
          "segment's strain passes payout_threshold); 'brake' pays out by tension in newtons");
    }
  }
  return warnings;
}

}  // namespace rov_tether
