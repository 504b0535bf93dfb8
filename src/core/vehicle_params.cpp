#include "rov_tether/core/vehicle_params.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace rov_tether
{
namespace
{

std::string number(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

// "" or "<field>[i]: must be <rule> (got <value>)" for the first component breaking the rule.
template <typename Vector, typename Rule>
std::string checkEach(const char* field, const Vector& values, const char* rule, Rule ok)
{
  for (int i = 0; i < values.size(); ++i)
  {
    if (!std::isfinite(values[i]))
    {
      return std::string(field) + "[" + std::to_string(i) + "]: must be finite (got " + number(values[i]) + ")";
    }
    if (!ok(values[i]))
    {
      return std::string(field) + "[" + std::to_string(i) + "]: must be " + rule + " (got " + number(values[i]) + ")";
    }
  }
  return "";
}

std::string checkScalar(const char* field, double value, const char* rule, bool ok)
{
  if (!std::isfinite(value))
  {
    return std::string(field) + ": must be finite (got " + number(value) + ")";
  }
  return ok ? "" : std::string(field) + ": must be " + rule + " (got " + number(value) + ")";
}

}  // namespace

Status VehicleParams::validate() const
{
  const auto positive = [](double x) { return x > 0.0; };
  const auto nonNegative = [](double x) { return x >= 0.0; };
  const auto withinReach = [](double x) { return std::abs(x) <= kMaxOffset; };
  const std::string problems[] = {
      checkScalar("mass", mass, "> 0 kg", mass > 0.0),
      checkScalar("displaced_volume", displaced_volume, ">= 0 m^3", displaced_volume >= 0.0),
      checkScalar("water_density", water_density, "> 0 kg/m^3", water_density > 0.0),
      checkScalar("gravity", gravity, ">= 0 m/s^2", gravity >= 0.0),
      checkEach("inertia", inertia, "> 0 kg m^2", positive),
      checkEach("center_of_gravity", center_of_gravity, "within +-100 m", withinReach),
      checkEach("center_of_buoyancy", center_of_buoyancy, "within +-100 m", withinReach),
      checkEach("added_mass", added_mass, ">= 0", nonNegative),
      checkEach("linear_damping", linear_damping, ">= 0", nonNegative),
      checkEach("quadratic_damping", quadratic_damping, ">= 0", nonNegative),
      checkEach("thrust_limit", thrust_limit, ">= 0", nonNegative),
      checkEach("size", size, "> 0 m", positive),
  };
  for (const auto& problem : problems)
  {
    if (!problem.empty())
    {
      return Status::error(problem);
    }
  }
  // Principal moments of a rigid body: each at most the sum of the other two (equal for a flat plate).
  for (int i = 0; i < 3; ++i)
  {
    const double others = inertia[(i + 1) % 3] + inertia[(i + 2) % 3];
    if (inertia[i] > others * (1.0 + 1e-9))
    {
      return Status::error("inertia: [" + number(inertia[0]) + ", " + number(inertia[1]) + ", " + number(inertia[2]) +
                           "] is no rigid body's (each principal moment must be at most the sum of the other two)");
    }
  }
  return Status::success();
}

std::string waterMismatch(const VehicleParams& vehicle, double water_density)
{
  if (vehicle.water_density == water_density)
  {
    return "";
  }
  // Its buoyancy in water of density rho, and how heavy or light that leaves it.
  const auto afloat = [&vehicle](double rho)
  {
    const double buoyancy = rho * vehicle.gravity * vehicle.displaced_volume;
    const double net = vehicle.weight() - buoyancy;
    char text[96];
    std::snprintf(text, sizeof text, "%.4g N, %.4g N %s", buoyancy, std::abs(net), net >= 0.0 ? "heavy" : "light");
    return std::string(text);
  };
  char densities[160];
  std::snprintf(densities, sizeof densities, "its water_density %.6g kg/m^3 is not the tether's %.6g kg/m^3",
                vehicle.water_density, water_density);
  return std::string(densities) + ": its buoyancy is " + afloat(vehicle.water_density) +
         " in water, where in the tether's water it would be " + afloat(water_density) + " (set the two alike)";
}

}  // namespace rov_tether
