#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "rov_tether/core/tether_params.hpp"

// The parameter table: every parameter's type, unit, range, choices and meaning, and the README table made from it.
namespace rov_tether
{
namespace
{

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
constexpr bool kOpen = true;
constexpr bool kClosed = false;
constexpr bool kLive = true;
constexpr bool kAtStart = false;

/// %g, with exponents written short (1e-08 -> 1e-8, 1e+05 -> 1e5) and a whole double keeping ".0"; NaN and
/// infinities as YAML writes them (.nan, .inf, -.inf).
std::string formatNumber(double value, bool integer)
{
  if (std::isnan(value))
  {
    return ".nan";
  }
  if (std::isinf(value))
  {
    return value > 0.0 ? ".inf" : "-.inf";  // YAML's, as .nan (the exponent below would be no int)
  }
  const double exponent10 = value != 0.0 ? std::log10(std::abs(value)) : 0.0;
  if (value != 0.0 && std::abs(exponent10) >= 4.0 && exponent10 == std::round(exponent10))
  {
    return std::string(value < 0.0 ? "-" : "") + "1e" + std::to_string(static_cast<int>(exponent10));
  }
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  std::string text = buffer;
  const auto e = text.find('e');
  if (e != std::string::npos)
  {
    std::string mantissa = text.substr(0, e);
    std::string exponent = text.substr(e + 1);
    const bool negative = exponent[0] == '-';
    exponent = exponent.substr(1);
    exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
    return mantissa + "e" + (negative ? "-" : "") + exponent;
  }
  if (!integer && text.find('.') == std::string::npos && std::abs(value) < 1e4)
  {
    text += ".0";
  }
  return text;
}

std::string formatRange(const ParameterInfo& info)
{
  if (!info.range.empty())
  {
    return info.range;
  }
  std::string choices;
  for (const ParameterChoice& choice : parameterChoices(info.name))
  {
    choices += (choices.empty() ? "`" : ", `") + choice.value + "`";
  }
  if (!choices.empty())
  {
    return choices;
  }
  if (std::isnan(info.min))
  {
    return "";
  }
  const bool integer = info.type.rfind("int", 0) == 0;
  return std::string(info.min_open ? "(" : "[") + formatNumber(info.min, integer) + ", " +
         formatNumber(info.max, integer) + (info.max_open ? ")" : "]");
}

}  // namespace

const std::vector<ParameterChoice>& parameterChoices(const std::string& name)
{
  // The choices of each string parameter, in documentation order (the README's range column, the .cfg's enums).
  static const std::vector<std::pair<std::string, std::vector<ParameterChoice>>> choices = {
      {"solver",
       {{"pbd", "red-black PBD (vectorised)"},
        {"pbd_sequential", "sequential order of the paper"},
        {"xpbd", "XPBD: stiffness EA, tension independent of iterations"},
        {"lumped_mass", "explicit springs; needs h < critical step"},
        {"direct", "Newton with an exact banded solve: exact length and tension"}}},
      {"drag_model",
       {{"damping", "velocity damping of the paper (drag)"}, {"morison", "quadratic Morison drag with added mass"}}},
      {"winch_mode",
       {{"brake", "a drum held by a brake that slips at brake_tension"},
        {"constant_tension", "pay out above, reel in below target_tension"},
        {"speed", "pay out / reel in at winch_speed"},
        {"locked", "deployed length fixed"},
        {"strain", "the rule of the paper: pay out past payout_threshold strain"}}},
  };
  static const std::vector<ParameterChoice> none;
  for (const auto& [parameter, list] : choices)
  {
    if (parameter == name)
    {
      return list;
    }
  }
  return none;
}

const std::vector<ParameterInfo>& parameterInfo()
{
  // name, type, unit, min, max, min open, max open, range as the README states it (when not [min, max]),
  // meaning, live (dynamic_reconfigure). Order: documentation order, as parameterTable().
  static const std::vector<ParameterInfo> table = {
      {"cable_length", "double", "m", 0.0, 1e5, kOpen, kClosed, "", "all cable, on the spool or deployed", kAtStart},
      {"segment_length", "double or `auto`", "m", 1e-3, 100.0, kClosed, kClosed, "", "rest length of one segment",
       kAtStart},
      {"shape_tolerance", "double", "m", 0.0, 100.0, kOpen, kClosed, "",
       "`segment_length: auto`: chord error dL^2 / (8 R) per segment", kAtStart},
      {"min_bend_radius", "double", "m", 0.0, 1e6, kOpen, kClosed, "",
       "`segment_length: auto`: the scene's tightest radius (a catenary: H / w)", kAtStart},
      {"initial_deployed_length", "double", "m", 0.0, 1e5, kOpen, kClosed, "[min_deployed_length, cable_length]",
       "deployed at start and after a reset", kAtStart},
      {"time_step", "double", "s", 1e-5, 0.1, kClosed, kClosed, "", "internal fixed step", kLive},
      {"solver", "string", "-", kNone, kNone, kClosed, kClosed, "", "method (see The model)", kLive},
      {"substeps", "int", "-", 1, 10000, kClosed, kClosed, "", "sub-steps per `time_step`", kLive},
      {"iterations", "int or `auto`", "-", 1, 1000, kClosed, kClosed, "",
       "constraint sweeps per sub-step (`direct`: the most Newton iterations, but for a diverged sub-step's rescue); "
       "`auto`: from `stretch_tolerance` "
       "(`direct`: 10; `lumped_mass`: chooses substeps)",
       kLive},
      {"over_relaxation", "double", "-", 0.5, 1.95, kClosed, kClosed, "",
       "`pbd`: each correction times this; 1 = the paper's", kLive},
      {"solver_tolerance", "double", "-", 1e-14, 0.1, kClosed, kClosed, "",
       "`direct`: Newton stops when every residual is below this x its segment length", kLive},
      {"stretch_tolerance", "double", "-", 0.0, 1.0, kOpen, kClosed, "",
       "`iterations: auto`: residual stretch aimed for (`pbd`, `xpbd`)", kAtStart},
      {"bending", "bool", "-", kNone, kNone, kClosed, kClosed, "",
       "the paper's (i, i+2) bending constraints (pbd); false also turns off `bending_stiffness` (xpbd, direct)",
       kLive},
      {"drag", "double", "-", 0.0, 1.0, kOpen, kClosed, "",
       "velocity kept per 0.02 s reference step (rate `-ln(drag)/0.02` 1/s)", kLive},
      {"noise", "double", "m", 0.0, 1.0, kClosed, kClosed,
       "[0, 1.0], a sub-step's share (`noise` (h / 0.02 s)^1.5) at most `segment_length` / 10",
       "random displacement half-width per axis per 0.02 s reference step", kLive},
      {"seed", "int", "-", 0.0, 9e15, kClosed, kClosed, "", "noise seed; same seed, same run", kAtStart},
      {"weight_in_water", "double", "N/m", -1e4, 1e4, kClosed, kClosed,
       "[-1e4, 1e4], and |weight_in_water| x cable_length, with the attachments' loads (and above "
       "`water_surface_z` the weight in air), < axial_stiffness with `direct` or `lumped_mass`; with "
       "`water_surface_z`, at most mass_per_length x g",
       "net weight, positive sinks, 0 neutrally buoyant", kLive},
      {"mass_per_length", "double", "kg/m", 0.0, 1e4, kOpen, kClosed, "", "mass, for weight and tension", kLive},
      {"axial_stiffness", "double", "N", 0.0, 1e12, kOpen, kClosed,
       "(0, 1e12], and above |weight_in_water| x cable_length, with the attachments' loads (and above "
       "`water_surface_z` the weight in air), with `direct` or `lumped_mass`",
       "EA: `xpbd`, `lumped_mass`, `direct` stiffness; `pbd`: only the scale of T/EA", kLive},
      {"axial_damping", "double", "N s", 0.0, 1e12, kClosed, kClosed, "",
       "BA: Kelvin-Voigt axial damping (`direct`, `xpbd`, `lumped_mass`), tension EA e + BA de/dt; 0 = none", kLive},
      {"bending_stiffness", "double", "N m^2", 0.0, 1e9, kClosed, kClosed, "",
       "EI of `xpbd`'s and `direct`'s bending; 0 = none", kLive},
      {"drag_model", "string", "-", kNone, kNone, kClosed, kClosed, "", "the paper's damping or Morison drag", kLive},
      {"diameter", "double", "m", 0.0, 10.0, kOpen, kClosed, "", "outer diameter (Morison, added mass)", kAtStart},
      {"water_density", "double", "kg/m^3", 0.0, 1e5, kClosed, kClosed, "", "density of the water", kAtStart},
      {"normal_drag_coefficient", "double", "-", 0.0, 100.0, kClosed, kClosed, "", "Morison, flow across the cable",
       kLive},
      {"tangential_drag_coefficient", "double", "-", 0.0, 100.0, kClosed, kClosed, "",
       "Morison, flow along the cable (area pi d)", kLive},
      {"added_mass_coefficient", "double", "-", 0.0, 100.0, kClosed, kClosed, "",
       "Morison: added mass C_a rho pi d^2 / 4 per metre", kLive},
      {"current", "double[3]", "m/s", -100.0, 100.0, kClosed, kClosed, "each in [-100, 100]",
       "uniform water velocity, world frame", kAtStart},
      {"current_variation", "double", "m/s", 0.0, 100.0, kClosed, kClosed, "", "RMS of the slow, correlated variation",
       kLive},
      {"seabed_z", "double", "m", -1e5, 1e5, kClosed, kClosed, "[-1e5, 1e5] or absent (.nan)",
       "height of a flat seabed", kAtStart},
      {"water_surface_z", "double", "m", -1e5, 1e5, kClosed, kClosed, "[-1e5, 1e5] or absent (.nan)",
       "height of the water surface: above it no buoyancy, drag or added mass", kAtStart},
      {"seabed_friction", "double", "-", 0.0, 10.0, kClosed, kClosed, "", "Coulomb friction on the seabed", kLive},
      {"cable_friction", "double", "-", 0.0, 10.0, kClosed, kClosed, "",
       "Coulomb friction on another tether or itself (obstacles: their own `friction`)", kLive},
      {"winch_mode", "string", "-", kNone, kNone, kClosed, kClosed, "", "winch behaviour (see The model)", kLive},
      {"brake_tension", "double", "N", 0.0, 1e7, kClosed, kClosed, "", "`brake`: the spool tension at which it slips",
       kLive},
      {"winch_inertia", "double", "kg", 0.0, 1e6, kClosed, kClosed, "",
       "`brake`: the drum's mass at its radius; 0 = massless", kLive},
      {"target_tension", "double", "N", 0.0, 1e7, kClosed, kClosed, "", "`constant_tension`: the spool tension held",
       kLive},
      {"tension_deadband", "double", "N", 0.0, 1e7, kClosed, kClosed, "",
       "`constant_tension`: no winch motion within this of the target", kLive},
      {"winch_speed", "double", "m/s", -20.0, 20.0, kClosed, kClosed, "[-max_winch_speed, max_winch_speed]",
       "`speed` mode command, positive pays out", kLive},
      {"max_winch_speed", "double", "m/s", 0.0, 20.0, kOpen, kClosed, "", "limit in every mode", kLive},
      {"max_winch_acceleration", "double", "m/s^2", 0.0, 1000.0, kOpen, kClosed, "",
       "`speed` and `constant_tension`: the drive's limit (a drum pulled past `max_winch_pull` slips at once)", kLive},
      {"max_winch_pull", "double", "N", 0.0, 1e7, kClosed, kClosed,
       "0, or [target_tension - tension_deadband, 1e7] in constant_tension",
       "the motor's stall pull: no reel-in (any mode: `strain` reels in slack) goes on above it, and pulled harder "
       "a reeling-in drum pays out (`constant_tension`: at any time); `speed` standing or paying out holds any pull "
       "(its brake); 0 = 1.25 x the larger of `target_tension` + `tension_deadband` and `brake_tension`",
       kLive},
      {"payout_threshold", "double", "-", 0.0, 1.0, kOpen, kClosed, "",
       "`strain`: first-segment strain that starts a pay-out", kLive},
      {"reel_in_slack", "double", "-", 0.0, 100.0, kClosed, kClosed, "",
       "`strain`: reel in above (1 + this) x spool-vehicle distance", kLive},
      {"min_deployed_length", "double", "m", 0.0, 1e5, kOpen, kClosed, "[segment_length, cable_length]",
       "never reel in below this", kAtStart},
      {"max_vehicle_jump", "double", "m", 0.0, 1e4, kOpen, kClosed, "",
       "a step between vehicle samples dt apart larger than this + `max_vehicle_speed` dt is a jump", kLive},
      {"max_vehicle_speed", "double", "m/s", 0.0, 1e3, kClosed, kClosed, "",
       "fastest the vehicle moves; 0: a jump is any step beyond `max_vehicle_jump`", kLive},
  };
  return table;
}

std::string formatParamValue(const ParamValue& value)
{
  switch (value.index())
  {
    case 0:
      return std::get<bool>(value) ? "true" : "false";
    case 1:
      return std::to_string(std::get<std::int64_t>(value));
    case 2:
      return formatNumber(std::get<double>(value), false);
    case 3:
      return std::get<std::string>(value);
    default:
    {
      std::string out = "[";
      for (const double v : std::get<std::vector<double>>(value))
      {
        out += (out.size() > 1 ? ", " : "") + formatNumber(v, false);
      }
      return out + "]";
    }
  }
}

std::string parameterTableMarkdown()
{
  const TetherParams defaults;
  std::string out = "| name | type | unit | default | range | live | meaning |\n|---|---|---|---|---|---|---|\n";
  for (const ParameterInfo& info : parameterInfo())
  {
    const ParamValue value = getParameter(defaults, info.name);
    std::string shown = formatParamValue(value);
    if (value.index() == 3)
    {
      shown = "`" + shown + "`";
    }
    if (const auto* number = std::get_if<double>(&value); number != nullptr && std::isnan(*number))
    {
      shown = ".nan (none)";  // an optional height (seabed_z, water_surface_z)
    }
    out += "| `" + info.name + "` | " + info.type + " | " + info.unit + " | " + shown + " | " + formatRange(info) +
           " | " + (info.live ? "yes" : "") + " | " + info.meaning + " |\n";
  }
  return out;
}

}  // namespace rov_tether
