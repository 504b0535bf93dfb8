#include "rov_tether/core/tether_params.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "parameter_members.hpp"
#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/cable_sections.hpp"
#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{
namespace
{

using members::findMember;
using members::Member;
using members::Vector3;

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

/// The numeric value(s) of a parameter's field as doubles (three for a vector), whatever its `auto` flag.
std::vector<double> numericValues(const TetherParams& params, const std::string& name)
{
  const Member* member = findMember(name);
  return std::visit(
      [&params](auto field) -> std::vector<double>
      {
        const auto& value = params.*field;
        using Field = std::decay_t<decltype(value)>;
        if constexpr (std::is_same_v<Field, Vector3>)
        {
          return {value[0], value[1], value[2]};
        }
        else if constexpr (std::is_arithmetic_v<Field>)
        {
          return {static_cast<double>(value)};
        }
        else
        {
          return {};
        }
      },
      *member);
}

/// The largest length that both a and b are whole multiples of, to 1e-9 of the larger (Euclid's algorithm on
/// lengths); tiny when they have none that is not (a ratio no fraction of small numbers gives).
double commonDivisor(double a, double b)
{
  const double tolerance = 1e-9 * std::max(a, b);
  while (b > tolerance)
  {
    double rest = std::fmod(a, b);
    rest = rest > b - tolerance ? 0.0 : rest;
    a = b, b = rest;
  }
  return a;
}

/// The longest length every section's is a whole number of (the last one's, what is left, not counted; tiny when
/// they have none), 0 without sections: `segment_length: auto`'s segments divide it, so none straddles a boundary.
double sectionsCommonLength(const std::vector<CableSection>& sections)
{
  double common = 0.0;
  for (std::size_t s = 0; s + 1 < sections.size(); ++s)
  {
    const double length = sections[s].length;
    common = !(length > 0.0) ? common : common > 0.0 ? commonDivisor(common, length) : length;
  }
  return common;
}

/// The shortest segment `segment_length: auto` goes down to [m].
constexpr double kMinAutoSegment = 1.0e-3;

/// Below kMinAutoSegment, compared to 1e-9 as segmentCount() counts: a division that asks for exactly 1 mm
/// (1.001 m in 1,001 segments) gives 0.9999999999999998 mm, which is taken.
bool belowMinAutoSegment(double segment) { return segment < kMinAutoSegment * (1.0 - 1e-9); }

/// The longest segment that `length` is a whole number of and that is at most `longest` [m].
double wholeSegmentsWithin(double length, double longest)
{
  return length / std::max(1.0, std::ceil(length / longest - 1e-9));
}

/// The longest segment `segment_length: auto`'s chord rule allows: the chord error of a segment dL on a curve of
/// radius R is dL^2 / (8 R) (docs/references.md "How fine a cable needs to be") [m].
double chordRuleLongest(const TetherParams& p) { return std::sqrt(8.0 * p.min_bend_radius * p.shape_tolerance); }

}  // namespace

std::vector<std::string> TetherParams::validate() const
{
  std::vector<std::string> errors = validateMaterial();
  if (!errors.empty())
  {
    return errors;
  }
  const TetherParams whole = resolved();  // the relations hold for the values `auto` chooses
  // A cable hanging from one end carries at its top the weight in water of all of it, w L (all of cable_length paid
  // out: any winch may pay it out), and that stretches its top segment by w L / EA; a buoyant one (w < 0) floats up
  // from its lower end the same way. At 100% (kDivergenceLimit) or more no cable survives it and the solver takes
  // the segment for a blow-up: the cable was re-laid every step, as an attachment's load of EA or more was. A cable
  // in sections, with attachments (whose loads the top carries too) or with a water surface (above which it weighs
  // its mass g): CableSections::check, section by section.
  const double top = std::abs(whole.weight_in_water) * whole.cable_length;
  if (failsAtFullStrain(whole.solver) && whole.sections.empty() && !(top < kDivergenceLimit * whole.axial_stiffness))
  {
    errors.push_back(
        "weight_in_water = " + formatValue(weight_in_water) +
        " N/m: a hanging cable's top tension |weight_in_water| x cable_length = " +
        formatValue(std::abs(whole.weight_in_water)) + " N/m x " + formatValue(whole.cable_length) +
        " m = " + formatValue(top) + " N must be below axial_stiffness EA = " + formatValue(whole.axial_stiffness) +
        " N: its own weight would stretch the cable by w L / EA = " + formatValue(100.0 * top / whole.axial_stiffness) +
        "%, which no cable survives and solver " + toString(whole.solver) +
        " takes for a blow-up (a segment at 100% strain)");
  }
  if (errors.empty() && (!sections.empty() || !attachments.empty() || !std::isnan(water_surface_z)))
  {
    const auto material = CableSections::check(whole);
    errors.insert(errors.end(), material.begin(), material.end());
  }
  return errors;
}

std::vector<std::string> TetherParams::validateMaterial() const
{
  std::vector<std::string> errors;
  // Each field's own range, from the parameter table (the README, default.yaml and the .cfg agree with it).
  const TetherParams defaults;
  for (const ParameterInfo& info : parameterInfo())
  {
    if (std::isnan(info.min))
    {
      continue;  // a choice or a flag: its parser checks it
    }
    const std::vector<double> values = numericValues(*this, info.name);
    for (std::size_t k = 0; k < values.size(); ++k)
    {
      const ParamValue fallback = getParameter(defaults, info.name);
      if (std::isnan(values[k]) && std::holds_alternative<double>(fallback) && std::isnan(std::get<double>(fallback)))
      {
        continue;  // an optional height, absent (seabed_z, water_surface_z)
      }
      const std::string label = values.size() == 1 ? info.name : info.name + "[" + std::string(1, "xyz"[k % 3]) + "]";
      checkRange(errors, label, values[k], info.min, info.max, info.min_open, info.max_open);
    }
  }
  if (!errors.empty())
  {
    return errors;  // relations between fields are only meaningful when each field is sane
  }

  if (segment_length_auto)
  {
    // resolved() keeps segments at 1 mm at least: the chord rule asking for less is refused, not followed silently.
    const double longest = chordRuleLongest(*this);
    const double plain = wholeSegmentsWithin(cable_length, longest);
    if (belowMinAutoSegment(plain))
    {
      errors.push_back("segment_length: auto: shape_tolerance = " + formatValue(shape_tolerance) +
                       " m on min_bend_radius = " + formatValue(min_bend_radius) + " m asks for segments of " +
                       formatValue(plain) +
                       " m, below the 1 mm `auto` goes down to: raise shape_tolerance or min_bend_radius, or set "
                       "segment_length");
      return errors;
    }
    // The sections' boundaries can ask for shorter ones still (said so here, not as a segment_length out of its
    // range or straddling a boundary, values nobody set): lengths with no common length of 1 mm (1 m and 1.0005 m),
    // or two of 0.75 mm in a 1.5 mm section when 1.2 mm is the longest the chord rule allows.
    const double common = sectionsCommonLength(sections);
    if (common > 0.0 && belowMinAutoSegment(common))
    {
      // Lengths with no common measure (1 m and sqrt(2) m) leave Euclid's rounding, not a length: not said.
      const std::string longest_common = common >= 1e-6 ? " (the longest is " + formatValue(common) + " m)" : "";
      errors.push_back(
          "segment_length: auto: the sections' lengths have no common length of 1 mm or more for "
          "segments to divide" +
          longest_common + ": make them whole multiples of a longer segment, or set segment_length");
      return errors;
    }
    const double split = common > 0.0 ? wholeSegmentsWithin(common, longest) : 0.0;
    if (common > 0.0 && belowMinAutoSegment(split))
    {
      errors.push_back(
          "segment_length: auto: the sections' common length " + formatValue(common) + " m in segments of at most " +
          formatValue(longest) + " m (shape_tolerance = " + formatValue(shape_tolerance) +
          " m on min_bend_radius = " + formatValue(min_bend_radius) + " m) asks for segments of " + formatValue(split) +
          " m, below the 1 mm `auto` goes down to: make the sections' lengths whole multiples of a "
          "longer segment, raise shape_tolerance or min_bend_radius, or set segment_length");
      return errors;
    }
  }
  if (segment_length_auto || iterations_auto)
  {
    return resolved().validateMaterial();  // the relations hold for the values `auto` chooses
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
  if (water_surface_z <= seabed_z)  // both given (a NaN, absent, compares false)
  {
    relation("water_surface_z = " + formatValue(water_surface_z) + ": must be above seabed_z = " +
             formatValue(seabed_z) + " (there would be no water: the cable would weigh as in air)");
  }
  if (!std::isnan(water_surface_z) && weight_in_water > mass_per_length * CableLoading::kGravity)
  {
    // In water a cable weighs its mass g less its buoyancy rho g V, never more than mass g, unless the volume it
    // displaces is negative; with a surface, the cable above it weighs mass g, and would come out of the water
    // lighter (the rule attachments follow, CableSections::check).
    relation("weight_in_water = " + formatValue(weight_in_water) +
             " N/m: it weighs more in water than in air, mass_per_length x g = " + formatValue(mass_per_length) +
             " kg/m x " + formatValue(CableLoading::kGravity) +
             " m/s^2 = " + formatValue(mass_per_length * CableLoading::kGravity) +
             " N/m (it would displace a negative volume, and above water_surface_z weigh less): give mass_per_length "
             "at least " +
             formatValue(weight_in_water / CableLoading::kGravity) + " kg/m, or a smaller weight");
  }
  if (initial_deployed_length < min_deployed_length || initial_deployed_length > cable_length)
  {
    relation("initial_deployed_length = " + formatValue(initial_deployed_length) +
             ": must be in [min_deployed_length = " + formatValue(min_deployed_length) +
             ", cable_length = " + formatValue(cable_length) + "]");
  }
  // The direct solver (and the others) converge while a sub-step's random displacement stays well below a
  // segment (Noise.TheLargestAllowedNoiseNeverFailsTheDefaultSolver); a tenth of one is the bound.
  if (noiseAmplitude(subStep()) > kMaxNoisePerSegment * segment_length)
  {
    relation("noise = " + formatValue(noise) +
             ": a sub-step's random displacement noise x (h / 0.02 s)^1.5 = " + formatValue(noiseAmplitude(subStep())) +
             " m must not exceed segment_length / 10 = " + formatValue(kMaxNoisePerSegment * segment_length) +
             " m (noise up to " +
             formatValue(kMaxNoisePerSegment * segment_length / std::pow(subStep() / kReferenceStep, 1.5)) +
             " m here): larger ones fold the chain faster than the solver unfolds it");
  }
  if (std::abs(winch_speed) > max_winch_speed)
  {
    relation("winch_speed = " + formatValue(winch_speed) + ": must be in [-max_winch_speed, max_winch_speed] = [" +
             formatValue(-max_winch_speed) + ", " + formatValue(max_winch_speed) + "]");
  }
  // A constant_tension winch reels in while the spool tension is below target_tension - tension_deadband, and its
  // motor gives way at its stall pull: one that stalls below the band's lower edge stops (pulled harder, pays out)
  // before the tension ever reaches the band, so it can never hold its target. The derived pull (0) is 1.25 x
  // (target + deadband), always above it. brake_tension is left alone: the brake never reels in (its drum has no
  // stall pull), so no brake_tension contradicts max_winch_pull.
  if (winch_mode == WinchMode::kConstantTension && max_winch_pull > 0.0 &&
      max_winch_pull < target_tension - tension_deadband)
  {
    relation("max_winch_pull = " + formatValue(max_winch_pull) +
             ": in constant_tension mode must be 0 (derived) or at least target_tension - tension_deadband = " +
             formatValue(target_tension) + " - " + formatValue(tension_deadband) + " = " +
             formatValue(target_tension - tension_deadband) +
             ": the motor gives way before the winch reaches its band, so it can never hold its target");
  }
  return errors;
}

double TetherParams::effectiveMassPerLength() const
{
  if (drag_model != DragModel::kMorison)
  {
    return mass_per_length;
  }
  constexpr double kPi = 3.14159265358979323846;
  return mass_per_length + added_mass_coefficient * water_density * kPi * diameter * diameter / 4.0;
}

double TetherParams::criticalStep() const
{
  // The axial waves are the fastest, and added mass acts across the cable only: the cable's own mass. The
  // fastest mode (neighbours in opposite phase, omega = 2 sqrt(EA / mu) / L) is stable for h omega < 2
  // undamped; axial damping BA gives it the damping ratio zeta = BA / (L sqrt(EA mu)), and an explicit
  // step of a damped oscillator is stable for h omega < 2 (sqrt(1 + zeta^2) - zeta).
  const double zeta = axial_damping / (segment_length * std::sqrt(axial_stiffness * mass_per_length));
  // sqrt(1 + z^2) - z = 1 / (sqrt(1 + z^2) + z), the second without cancellation at large z.
  double step = segment_length / std::sqrt(axial_stiffness / mass_per_length) / (std::sqrt(1.0 + zeta * zeta) + zeta);
  // A cable in sections: its lightest, stiffest section's (an attachment only adds mass, which is slower).
  for (const CableSection& section : sections)
  {
    TetherParams own = *this;
    own.sections.clear(), own.attachments.clear();
    for (const auto& [name, value] : section.properties)
    {
      (void)setParameter(own, name, value);  // checked by validate(); a refused one leaves the tether's
    }
    step = std::min(step, own.criticalStep());
  }
  return step;
}

double TetherParams::winchPull() const
{
  return max_winch_pull > 0.0 ? max_winch_pull : 1.25 * std::max(target_tension + tension_deadband, brake_tension);
}

double TetherParams::largestOverSections(std::string_view name, double own) const
{
  double largest = sections.empty() ? own : 0.0;
  for (const CableSection& section : sections)
  {
    double value = own;
    for (const auto& [set, set_value] : section.properties)
    {
      value = set == name ? set_value : value;
    }
    largest = std::max(largest, value);
  }
  return largest;
}

TetherParams TetherParams::resolved() const
{
  TetherParams r = *this;
  if (segment_length_auto)
  {
    // Whole segments within the chord rule's longest, 1 mm at least (validate() refuses a rule asking for less; a
    // division asking for exactly 1 mm can give 0.9999999999999998 mm). Sections end on segment boundaries: the
    // longest such segment that every section's length (the last one's is what is left) is a whole number of.
    const double longest = chordRuleLongest(*this);
    const double common = sectionsCommonLength(sections);
    const double whole = belowMinAutoSegment(common) ? cable_length : common;
    r.segment_length = std::max(wholeSegmentsWithin(whole, longest), kMinAutoSegment);
    r.segment_length_auto = false;
  }
  if (iterations_auto)
  {
    if (solver == SolverType::kLumpedMass)
    {
      // Stretch is physical (T / EA) once the chain is stable: half the critical step.
      r.substeps = static_cast<int>(std::clamp(std::ceil(time_step / (0.5 * r.criticalStep())), 1.0, 10000.0));
    }
    else if (solver == SolverType::kDirect)
    {
      r.iterations = kDirectIterations;  // exact: it stops on solver_tolerance, this is only its limit
    }
    else
    {
      // Residual stretch of a hanging PBD chain: about L a h^2 / (2 n dL^2) (docs/references.md, N^2 g dt^2 /
      // (2 n L) with N = L / dL), a the weight's acceleration, at least 1 m/s^2 for the vehicle's pull.
      const double accel = std::max(std::abs(weight_in_water) / effectiveMassPerLength(), 1.0);
      const double h = r.subStep();
      const double n = cable_length * accel * h * h / (2.0 * stretch_tolerance * r.segment_length * r.segment_length);
      r.iterations = static_cast<int>(std::clamp(std::ceil(n), 1.0, 1000.0));
    }
    r.iterations_auto = false;
  }
  return r;
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
  // initial_deployed_length only matters at a reset, and a new solver takes the cable as it is: neither is
  // structure.
  return a.cable_length == b.cable_length && a.segment_length == b.segment_length;
}

}  // namespace rov_tether
