#include "rov_tether/ros/winch_service.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <vector>

namespace rov_tether::ros_layer
{
namespace
{
/// A request's number as the answer quotes it ("nan", not std::to_string's "-nan").
std::string quoted(double value)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%g", std::isnan(value) ? std::abs(value) : value);
  return text;
}

/// A parameter error (validate()'s, "name = value: ...") with, for a parameter that is no field of the request,
/// where it is changed instead; each such parameter hinted once (`hinted`).
std::string withHint(const std::string& error, const TetherParams& params, const std::string& reconfigure,
                     std::vector<std::string>* hinted)
{
  const auto& table = parameterInfo();
  const std::string name = error.substr(0, error.find(" = "));
  const auto info =
      std::find_if(table.begin(), table.end(), [&](const ParameterInfo& row) { return row.name == name; });
  const bool field =
      name == "winch_mode" || name == "winch_speed" || name == "brake_tension" || name == "target_tension";
  if (info == table.end() || field || std::find(hinted->begin(), hinted->end(), name) != hinted->end())
  {
    return error;
  }
  hinted->push_back(name);
  return error + "; " + name + " (now " + formatParamValue(getParameter(params, name)) +
         ") is no field of ~set_winch: " +
         (info->live ? "change it with dynamic_reconfigure (rosrun dynamic_reconfigure dynparam set " + reconfigure +
                           " " + name + " VALUE), then ask again"
                     : std::string("it is set at start (the node's parameters)"));
}
}  // namespace

std::string winchRequest(const SetWinch::Request& request, TetherParams* params_in_force, double* target_in_force,
                         const std::string& reconfigure)
{
  // Worked out on copies, handed back only when the request is taken: a refusal changes nothing the caller holds.
  TetherParams asked = *params_in_force;
  double asked_target = *target_in_force;
  TetherParams* params = &asked;
  double* target = &asked_target;
  if (!request.mode.empty() && !parseWinchMode(request.mode, &params->winch_mode))
  {
    return "mode '" + request.mode + "': expected brake, constant_tension, speed, locked or strain";
  }
  std::vector<std::string> problems;
  for (const auto& [value, field, name] :
       {std::tuple{request.brake_tension, &params->brake_tension, "brake_tension"},
        std::tuple{request.target_tension, &params->target_tension, "target_tension"}})
  {
    if (!(value >= 0.0))
    {
      return std::string(name) + " = " + quoted(value) + " N: must be >= 0 (0 keeps the current value)";
    }
    *field = value > 0.0 ? value : *field;
  }
  if (!std::isfinite(request.speed))
  {
    return "speed = " + quoted(request.speed) + " m/s: must be finite";
  }
  if (request.target_length < 0.0 || !std::isfinite(request.target_length))
  {
    return "target_length = " + quoted(request.target_length) + ": must be a finite length > 0 m, or 0 for none";
  }
  const bool speed_mode = params->winch_mode == WinchMode::kSpeed;
  if (!speed_mode)
  {
    // speed and target_length would do nothing: said, not taken silently.
    for (const auto& [value, name, unit] :
         {std::tuple{request.speed, "speed", " m/s"}, std::tuple{request.target_length, "target_length", " m"}})
    {
      if (value != 0.0)
      {
        problems.push_back(std::string(name) + " = " + quoted(value) + unit + ": acts in speed mode only, and the " +
                           "winch would be in " + toString(params->winch_mode) + " mode (send mode: speed with it)");
      }
    }
    *target = std::nan("");  // a target length lives in speed mode only
  }
  else if (request.mode.empty())
  {
    // The mode kept: a field left at 0 keeps what is in force, as the tensions do.
    params->winch_speed = request.speed != 0.0 ? request.speed : params->winch_speed;
    *target = request.target_length > 0.0 ? request.target_length : *target;
  }
  else
  {
    params->winch_speed = request.speed;
    *target = request.target_length > 0.0 ? request.target_length : std::nan("");
  }
  if (speed_mode && !std::isnan(*target) && params->winch_speed == 0.0)
  {
    problems.push_back("target_length = " + quoted(*target) + " m: needs a speed to go there at (speed is 0)");
  }
  std::vector<std::string> hinted;
  for (const std::string& error : params->validate())
  {
    problems.push_back(withHint(error, *params, reconfigure, &hinted));
  }
  // Checked against the new limits before anything changes.
  if (!std::isnan(*target) && !(*target >= params->min_deployed_length && *target <= params->cable_length))
  {
    problems.push_back("target_length = " + quoted(*target) + " m: must be in [min_deployed_length, " +
                       "cable_length] = [" + quoted(params->min_deployed_length) + ", " + quoted(params->cable_length) +
                       "] m");
  }
  std::string answer;
  for (const std::string& problem : problems)
  {
    answer += (answer.empty() ? "" : "; ") + problem;
  }
  if (answer.empty())
  {
    *params_in_force = asked;
    *target_in_force = asked_target;
  }
  return answer;
}

/// The answer to an accepted SetWinch request: the mode in force, its force, and any parameter warning.
std::string winchAnswer(const TetherParams& params, const std::string& requested_mode)
{
  std::string message = "winch " + toString(params.winch_mode);
  if (params.winch_mode == WinchMode::kBrake)
  {
    message += ", brake_tension " + std::to_string(params.brake_tension) + " N";
  }
  else if (params.winch_mode == WinchMode::kConstantTension)
  {
    message += ", target_tension " + std::to_string(params.target_tension) + " N";
  }
  for (const std::string& warning : parameterWarnings({{"winch_mode", requested_mode}}))
  {
    message += " (" + warning + ")";
  }
  return message;
}

}  // namespace rov_tether::ros_layer
