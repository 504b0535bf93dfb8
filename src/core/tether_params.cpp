#include "rov_tether/tether_params.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace rov_tether
{
namespace
{

using Member = std::variant<double TetherParams::*, int TetherParams::*, bool TetherParams::*,
                            std::int64_t TetherParams::*, SolverType TetherParams::*, WinchMode TetherParams::*>;

/// The one table of parameter names; order is documentation order.
const std::vector<std::pair<std::string, Member>>& parameterTable()
{
  static const std::vector<std::pair<std::string, Member>> table = {
      {"cable_length", &TetherParams::cable_length},
      {"segment_length", &TetherParams::segment_length},
      {"initial_deployed_length", &TetherParams::initial_deployed_length},
      {"time_step", &TetherParams::time_step},
      {"solver", &TetherParams::solver},
      {"iterations", &TetherParams::iterations},
      {"bending", &TetherParams::bending},
      {"drag", &TetherParams::drag},
      {"noise", &TetherParams::noise},
      {"seed", &TetherParams::seed},
      {"weight_in_water", &TetherParams::weight_in_water},
      {"mass_per_length", &TetherParams::mass_per_length},
      {"axial_stiffness", &TetherParams::axial_stiffness},
      {"winch_mode", &TetherParams::winch_mode},
      {"winch_speed", &TetherParams::winch_speed},
      {"max_winch_speed", &TetherParams::max_winch_speed},
      {"payout_threshold", &TetherParams::payout_threshold},
      {"reel_in_slack", &TetherParams::reel_in_slack},
      {"min_deployed_length", &TetherParams::min_deployed_length},
      {"max_vehicle_jump", &TetherParams::max_vehicle_jump},
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
    default:
      return "a string";
  }
}

std::string formatValue(double value)
{
  std::ostringstream out;
  out << value;
  return out.str();
}

/// Appends "name = value: must be in [min, max]" when value is outside [min, max] or not finite.
/// Open bounds are marked with `min_open` / `max_open`.
void checkRange(std::vector<std::string>& errors, const std::string& name, double value, double min, double max,
                bool min_open = false, bool max_open = false)
{
  const bool below = min_open ? !(value > min) : !(value >= min);
  const bool above = max_open ? !(value < max) : !(value <= max);
  if (std::isfinite(value) && !below && !above)
  {
    return;
  }
  std::ostringstream out;
  out << name << " = " << value << ": must be a finite number in " << (min_open ? "(" : "[") << min << ", " << max
      << (max_open ? ")" : "]");
  errors.push_back(out.str());
}

}  // namespace

std::vector<std::string> TetherParams::validate() const
{
  std::vector<std::string> errors;
  checkRange(errors, "cable_length", cable_length, 0.0, 1.0e5, true);
  checkRange(errors, "segment_length", segment_length, 1.0e-3, 100.0);
  checkRange(errors, "initial_deployed_length", initial_deployed_length, 0.0, 1.0e5, true);
  checkRange(errors, "time_step", time_step, 1.0e-5, 0.1);
  checkRange(errors, "iterations", iterations, 1, 1000);
  checkRange(errors, "drag", drag, 0.0, 1.0, true);
  checkRange(errors, "noise", noise, 0.0, 1.0);
  checkRange(errors, "seed", static_cast<double>(seed), 0.0, 9.0e15);
  checkRange(errors, "weight_in_water", weight_in_water, -1.0e4, 1.0e4);
  checkRange(errors, "mass_per_length", mass_per_length, 0.0, 1.0e4, true);
  checkRange(errors, "axial_stiffness", axial_stiffness, 0.0, 1.0e12, true);
  checkRange(errors, "max_winch_speed", max_winch_speed, 0.0, 20.0, true);
  checkRange(errors, "winch_speed", winch_speed, -20.0, 20.0);
  checkRange(errors, "payout_threshold", payout_threshold, 0.0, 1.0, true);
  checkRange(errors, "reel_in_slack", reel_in_slack, 0.0, 100.0);
  checkRange(errors, "min_deployed_length", min_deployed_length, 0.0, 1.0e5, true);
  checkRange(errors, "max_vehicle_jump", max_vehicle_jump, 0.0, 1.0e4, true);
  if (!errors.empty())
  {
    return errors;  // relations between fields are only meaningful when each field is sane
  }

  // Relations between fields, each named with the value it contradicts.
  auto relation = [&errors](const std::string& message) { errors.push_back(message); };
  if (segment_length > cable_length)
  {
    relation("segment_length = " + formatValue(segment_length) +
             ": must not exceed cable_length = " + formatValue(cable_length));
  }
  if (cable_length / segment_length > 2.0e6)
  {
    relation("segment_length = " + formatValue(segment_length) + ": cable_length / segment_length = " +
             formatValue(cable_length / segment_length) + " exceeds 2e6 segments");
  }
  if (min_deployed_length < segment_length || min_deployed_length > cable_length)
  {
    relation("min_deployed_length = " + formatValue(min_deployed_length) + ": must be in [segment_length = " +
             formatValue(segment_length) + ", cable_length = " + formatValue(cable_length) + "]");
  }
  if (initial_deployed_length < min_deployed_length || initial_deployed_length > cable_length)
  {
    relation("initial_deployed_length = " + formatValue(initial_deployed_length) +
             ": must be in [min_deployed_length = " + formatValue(min_deployed_length) +
             ", cable_length = " + formatValue(cable_length) + "]");
  }
  if (std::abs(winch_speed) > max_winch_speed)
  {
    relation("winch_speed = " + formatValue(winch_speed) + ": must be in [-max_winch_speed, max_winch_speed] = [" +
             formatValue(-max_winch_speed) + ", " + formatValue(max_winch_speed) + "]");
  }
  return errors;
}

double TetherParams::dampingRate() const { return -std::log(drag) / kReferenceStep; }

double TetherParams::dampingFactor(double dt) const { return std::exp(-dampingRate() * dt); }

double TetherParams::noiseAmplitude(double dt) const { return noise * std::pow(dt / kReferenceStep, 1.5); }

std::size_t TetherParams::segmentCount() const
{
  // A tiny tolerance keeps 10 m / 0.1 m at 100 segments despite rounding.
  return static_cast<std::size_t>(std::ceil(cable_length / segment_length - 1e-9));
}

bool sameStructure(const TetherParams& a, const TetherParams& b)
{
  // initial_deployed_length only matters at a reset, so it is not structure.
  return a.cable_length == b.cable_length && a.segment_length == b.segment_length && a.solver == b.solver;
}

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

std::string setParameter(TetherParams& params, const std::string& name, const ParamValue& value)
{
  const Member* member = findMember(name);
  if (member == nullptr)
  {
    return "unknown parameter '" + name + "'";
  }
  const std::string wrong_type = "parameter '" + name + "': wrong type (" + typeName(value) + "), expected ";
  return std::visit(
      [&](auto field) -> std::string
      {
        using Field = std::remove_reference_t<decltype(params.*field)>;
        Field& target = params.*field;
        if constexpr (std::is_same_v<Field, double>)
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
          return wrong_type + "a number";
        }
        else if constexpr (std::is_same_v<Field, int> || std::is_same_v<Field, std::int64_t>)
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
        else if constexpr (std::is_same_v<Field, bool>)
        {
          if (const auto* b = std::get_if<bool>(&value))
          {
            target = *b;
            return "";
          }
          return wrong_type + "true or false";
        }
        else if constexpr (std::is_same_v<Field, SolverType>)
        {
          const auto* s = std::get_if<std::string>(&value);
          if (s == nullptr || !parseSolver(*s, &target))
          {
            return "parameter 'solver': expected one of pbd, pbd_sequential";
          }
          return "";
        }
        else
        {
          const auto* s = std::get_if<std::string>(&value);
          if (s == nullptr || !parseWinchMode(*s, &target))
          {
            return "parameter 'winch_mode': expected one of passive, locked, speed";
          }
          return "";
        }
      },
      *member);
}

ParamValue getParameter(const TetherParams& params, const std::string& name)
{
  const Member* member = findMember(name);
  if (member == nullptr)
  {
    throw std::out_of_range("unknown parameter '" + name + "'");
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
        else if constexpr (std::is_same_v<Field, SolverType> || std::is_same_v<Field, WinchMode>)
        {
          return toString(value);
        }
        else
        {
          return value;
        }
      },
      *member);
}

std::string toString(SolverType solver) { return solver == SolverType::kPbd ? "pbd" : "pbd_sequential"; }

std::string toString(WinchMode mode)
{
  switch (mode)
  {
    case WinchMode::kPassive:
      return "passive";
    case WinchMode::kLocked:
      return "locked";
    default:
      return "speed";
  }
}

bool parseSolver(const std::string& text, SolverType* solver)
{
  if (text == "pbd")
  {
    *solver = SolverType::kPbd;
    return true;
  }
  if (text == "pbd_sequential")
  {
    *solver = SolverType::kPbdSequential;
    return true;
  }
  return false;
}

bool parseWinchMode(const std::string& text, WinchMode* mode)
{
  for (WinchMode candidate : {WinchMode::kPassive, WinchMode::kLocked, WinchMode::kSpeed})
  {
    if (text == toString(candidate))
    {
      *mode = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace rov_tether
