#include "rov_tether/core/cable_sections.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rov_tether/core/constraint_solver.hpp"

namespace rov_tether
{
namespace
{

// The fields of SectionMaterial by parameter name: the one list properties() and make() read.
using Field = double SectionMaterial::*;
const std::vector<std::pair<std::string, Field>>& fields()
{
  static const std::vector<std::pair<std::string, Field>> table = {
      {"mass_per_length", &SectionMaterial::mass_per_length},
      {"weight_in_water", &SectionMaterial::weight_in_water},
      {"diameter", &SectionMaterial::diameter},
      {"axial_stiffness", &SectionMaterial::axial_stiffness},
      {"bending_stiffness", &SectionMaterial::bending_stiffness},
      {"axial_damping", &SectionMaterial::axial_damping},
      {"normal_drag_coefficient", &SectionMaterial::normal_drag_coefficient},
      {"tangential_drag_coefficient", &SectionMaterial::tangential_drag_coefficient},
      {"added_mass_coefficient", &SectionMaterial::added_mass_coefficient},
  };
  return table;
}

std::string number(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

/// The load each section of a hanging cable carries, against its EA (CableSections::check, for the solvers that
/// take a segment at 100% strain for a blow-up). A hanging cable's tension at a point is the net weight of what
/// hangs below it: hung from the spool, the cable between the point and the vehicle end with the attachments on it
/// (a clump adds its weight, a float takes off its lift); hung from the vehicle (a spool below it, or buoyant
/// material floating up from the spool), the rest. All of cable_length counts (any winch may pay it out). Between
/// two breaks (a section's end, an attachment) the load grows linearly, so its most is at one of their ends; at the
/// section's EA or more it stretches the segment there by 100% (kDivergenceLimit), which no cable survives and the
/// solver takes for a blow-up (TetherParams::validate makes the same check of a uniform cable alone: w L < EA).
/// With water_surface_z set any part of the cable may be above the surface (where the spool is, is not a
/// parameter), where it weighs its mass g (mass_per_length g, an attachment's mass g) instead of its weight in
/// water: each piece counts at whichever of the two the load at hand is largest with, so the bound holds wherever
/// the surface cuts the cable. `attachments`: those whose own values are valid (the others are refused for
/// themselves).
std::vector<std::string> hangingLoadErrors(const TetherParams& params, const CableSections& made,
                                           const std::vector<CableAttachment>& attachments)
{
  const auto& materials = made.materials();
  const auto& ends = made.ends();
  const bool surface = !std::isnan(params.water_surface_z);
  const double g = CableLoading::kGravity;
  std::vector<double> from(materials.size() + 1, 0.0);  // each section boundary's distance from the vehicle end [m]
  for (std::size_t s = 0; s < materials.size(); ++s)
  {
    from[s + 1] =
        s + 1 == materials.size() ? params.cable_length : static_cast<double>(ends[s]) * params.segment_length;
  }
  // The downward load per metre of each section, and of each attachment, in water and (with a surface) in air.
  struct Load
  {
    double at = 0.0;                // where (an attachment) [m from the vehicle end]
    double water = 0.0, air = 0.0;  // [N or N/m], down positive
  };
  std::vector<Load> points;
  std::vector<double> breaks(from.begin(), from.end());
  for (const CableAttachment& attachment : attachments)
  {
    points.push_back({attachment.arc_length_from_vehicle, -attachment.net_buoyancy, attachment.mass * g});
    breaks.push_back(attachment.arc_length_from_vehicle);
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  // The load between the vehicle end and x (the attachments at x too when `at_x`), at its least and its most.
  const auto below = [&](double x, bool at_x)
  {
    std::pair<double, double> load{0.0, 0.0};
    const auto add = [&](double water, double air)
    {
      load.first += surface ? std::min(water, air) : water;
      load.second += surface ? std::max(water, air) : water;
    };
    for (std::size_t s = 0; s < materials.size(); ++s)
    {
      const double length = std::max(0.0, std::min(x, from[s + 1]) - from[s]);
      add(materials[s].weight_in_water * length, materials[s].mass_per_length * g * length);
    }
    for (const Load& point : points)
    {
      if (point.at < x || (at_x && point.at == x))
      {
        add(point.water, point.air);
      }
    }
    return load;
  };
  const auto total = below(params.cable_length, true);
  std::vector<std::string> errors;
  for (std::size_t s = 0; s < materials.size(); ++s)
  {
    double pull = 0.0;
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b)
    {
      if (!(breaks[b] >= from[s] && breaks[b + 1] <= from[s + 1]))
      {
        continue;
      }
      // Just above the lower break (its attachments included) and just below the upper one (its not).
      for (const auto& [lo, hi] : {below(breaks[b], true), below(breaks[b + 1], false)})
      {
        // Hung from the spool the load below the point, hung from the vehicle the load above it.
        pull = std::max({pull, std::abs(lo), std::abs(hi), std::abs(total.first - lo), std::abs(total.second - hi)});
      }
    }
    const double stiffness = materials[s].axial_stiffness;
    if (!(pull < kDivergenceLimit * stiffness))
    {
      const bool loads = !points.empty() || surface;
      errors.push_back((params.sections.empty() ? std::string("the cable")
                                                : "sections: the cable from " + number(from[s]) + " m to " +
                                                      number(from[s + 1]) + " m from the vehicle") +
                       " (weight_in_water = " + number(materials[s].weight_in_water) +
                       " N/m, axial_stiffness EA = " + number(stiffness) + " N): " +
                       (loads ? std::string("the load hanging from it, up to ") + number(pull) +
                                    " N (the cable's weight below it" +
                                    (points.empty() ? "" : " with its attachments' net loads") +
                                    (surface ? ", in water or, above water_surface_z, in air (mass g)" : "") + ")"
                              : std::string("the cable's own weight in water hanging from it, up to ") + number(pull) +
                                    " N (w L of the sections below it)") +
                       ", must be below its EA: it would stretch it by " + number(100.0 * pull / stiffness) +
                       "%, which no cable survives and the solver takes for a blow-up (a segment at 100% strain)");
    }
  }
  return errors;
}

}  // namespace

SectionMaterial SectionMaterial::of(const TetherParams& params)
{
  SectionMaterial material;
  for (const auto& [name, field] : fields())
  {
    material.*field = std::get<double>(getParameter(params, name));
  }
  return material;
}

void SectionMaterial::applyTo(TetherParams* params) const
{
  for (const auto& [name, field] : fields())
  {
    setParameter(*params, name, this->*field);
  }
}

bool SectionMaterial::operator==(const SectionMaterial& other) const
{
  return std::all_of(fields().begin(), fields().end(),
                     [&](const auto& entry) { return this->*entry.second == other.*entry.second; });
}

const std::vector<std::string>& CableSections::properties()
{
  static const std::vector<std::string> names = []
  {
    std::vector<std::string> result;
    for (const auto& entry : fields())
    {
      result.push_back(entry.first);
    }
    return result;
  }();
  return names;
}

Status CableSections::make(const TetherParams& params, const std::vector<CableSection>& sections, CableSections* out)
{
  const std::size_t segments = params.segmentCount();
  CableSections made;
  if (sections.empty())
  {
    made.materials_ = {SectionMaterial::of(params)};
    made.ends_ = {segments};
    *out = std::move(made);
    return Status::success();
  }
  std::vector<std::string> errors;
  double covered = 0.0;       // [m] by the sections before the one at hand
  std::size_t end = 0;        // segments from the vehicle end
  bool lengths_given = true;  // every length before the one at hand is one (else `covered` means nothing)
  for (std::size_t s = 0; s < sections.size(); ++s)
  {
    const CableSection& section = sections[s];
    const std::string which = "section " + std::to_string(s + 1) + " of " + std::to_string(sections.size());
    const bool last = s + 1 == sections.size();
    // Where the section ends. A length that is wrong ends only this part: the section's properties are checked
    // whatever is wrong with its length, so that every error of every section is said in one message (a missing
    // length hid those of its own properties and of every later section's left-out length).
    [&]
    {
      double length = section.length;
      if (std::isnan(length) && !last)
      {
        // NaN is a length left out (CableSection::length): a missing key, not a bad value.
        errors.push_back(which + ": length: missing (only the last section may leave it out: it runs to the drum)");
        lengths_given = false;
        return;
      }
      if (std::isnan(length))
      {
        if (!lengths_given)
        {
          return;  // what the sections before it cover is not known
        }
        length = params.cable_length - covered;  // runs to the drum
        if (!(length > 0.0))
        {
          errors.push_back(which + ": the sections before it cover " + number(covered) + " m of the " +
                           number(params.cable_length) + " m cable, so none is left for it to run to the drum");
          return;
        }
      }
      else if (!std::isfinite(length) || !(length > 0.0))
      {
        errors.push_back(which + ": length = " + number(length) + " m: must be finite and > 0");
        lengths_given = false;
        return;
      }
      covered += length;
      if (last)
      {
        if (lengths_given && std::abs(covered - params.cable_length) > 1e-6 * params.segment_length)
        {
          errors.push_back("their lengths add up to " + number(covered) + " m, not cable_length " +
                           number(params.cable_length) +
                           " m (leave the last section's length out to run it to the drum)");
          return;
        }
        end = segments;  // what is left, a short last segment included
      }
      else
      {
        const double count = length / params.segment_length;
        if (std::abs(count - std::round(count)) > 1e-6 || std::round(count) < 1.0)
        {
          errors.push_back(which + ": length " + number(length) + " m is not a whole number of segments of " +
                           number(params.segment_length) + " m (segments never straddle a section boundary)");
          return;
        }
        end += static_cast<std::size_t>(std::round(count));
        if (lengths_given && end >= segments)
        {
          errors.push_back(which + ": ends " + number(covered) + " m from the vehicle, at or beyond the cable's " +
                           number(params.cable_length) + " m, and is not the last section");
          return;
        }
      }
    }();
    // The section's material is the tether's parameters with its properties set, checked by the parameter
    // table's own ranges (and TetherParams::validate's relations) so a section is held to what the tether is.
    TetherParams own = params;
    own.sections.clear(), own.attachments.clear();  // its own material only (validate() checks those)
    std::vector<std::string> seen;
    bool named = true;
    for (const auto& [name, value] : section.properties)
    {
      const auto& allowed = properties();
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      {
        errors.push_back(which + ": '" + name + "' is not a property a section may set");
        named = false;
        continue;
      }
      if (std::find(seen.begin(), seen.end(), name) != seen.end())
      {
        errors.push_back(which + ": '" + name + "' is set twice");
        named = false;
        continue;
      }
      seen.push_back(name);
      const std::string error = setParameter(own, name, value);
      if (!error.empty())
      {
        errors.push_back(which + ": " + error);
        named = false;
      }
    }
    if (!named)
    {
      continue;
    }
    for (const std::string& error : own.validateMaterial())
    {
      errors.push_back(which + ": " + error);
    }
    const SectionMaterial material = SectionMaterial::of(own);
    if (!made.materials_.empty() && made.materials_.back() == material)
    {
      made.ends_.back() = end;  // the same material as the section before: one section
    }
    else
    {
      made.materials_.push_back(material);
      made.ends_.push_back(end);
    }
  }
  if (!errors.empty())
  {
    std::string text = "sections: ";
    for (std::size_t i = 0; i < errors.size(); ++i)
    {
      text += (i > 0 ? "; " : "") + errors[i];
    }
    return Status::error(text);
  }
  *out = std::move(made);
  return Status::success();
}

std::vector<std::string> CableSections::check(const TetherParams& params)
{
  std::vector<std::string> errors;
  CableSections made;
  const Status sections = make(params, params.sections, &made);
  if (!sections)
  {
    errors.push_back(sections.message);
  }
  else if (params.bending && made.materials().size() > 1)
  {
    // direct solves a bending cable as a rod, which carries compression: a section of no bending stiffness
    // in it would push where a limp cable cannot.
    const auto& materials = made.materials();
    const bool bends = std::any_of(materials.begin(), materials.end(),
                                   [](const SectionMaterial& m) { return m.bending_stiffness > 0.0; });
    for (std::size_t s = 0; bends && s < materials.size(); ++s)
    {
      if (materials[s].bending_stiffness == 0.0)
      {
        errors.push_back(
            "sections: a section of bending_stiffness 0 in a cable that bends elsewhere would carry "
            "compression (a bending cable is solved as a rod); give it a small bending_stiffness, or "
            "set bending false");
        break;
      }
    }
  }
  if (sections && params.solver != SolverType::kDirect)
  {
    const SectionMaterial own = SectionMaterial::of(params);
    for (const SectionMaterial& material : made.materials())
    {
      if (material.axial_stiffness != own.axial_stiffness || material.axial_damping != own.axial_damping ||
          material.bending_stiffness != own.bending_stiffness)
      {
        errors.push_back(
            "sections: a section of its own axial_stiffness, axial_damping or bending_stiffness needs "
            "solver direct (the others take one stiffness for the whole cable); solver is " +
            formatParamValue(getParameter(params, "solver")));
        break;
      }
    }
  }
  std::vector<std::string> names;
  std::vector<CableAttachment> loads;  // the attachments whose own place and load are valid
  for (std::size_t a = 0; a < params.attachments.size(); ++a)
  {
    const CableAttachment& attachment = params.attachments[a];
    // Named as the readers name it: attachments[k] (from 0, in the order written) and its name.
    const std::string which =
        "attachments[" + std::to_string(a) + "]" + (attachment.name.empty() ? "" : " '" + attachment.name + "'");
    if (attachment.name.empty())
    {
      errors.push_back(which + ": name missing");
    }
    else if (std::find(names.begin(), names.end(), attachment.name) != names.end())
    {
      errors.push_back(which + ": the name is used twice");
    }
    names.push_back(attachment.name);
    const std::size_t before = errors.size();
    const double arc = attachment.arc_length_from_vehicle;
    if (!(arc > 0.0 && arc <= params.cable_length))
    {
      errors.push_back(which + ": arc_length_from_vehicle = " + number(arc) + " m: must be in (0, cable_length " +
                       number(params.cable_length) + " m]" +
                       (arc > 0.0 ? std::string(" (it is beyond the drum end)")
                                  : std::string(" (a body at the vehicle end is the vehicle's)")));
    }
    const std::vector<std::pair<const char*, double>> non_negative = {
        {"mass", attachment.mass},
        {"added_mass", attachment.added_mass},
        {"drag_area", attachment.drag_area},
        {"drag_coefficient", attachment.drag_coefficient}};
    for (const auto& [field, value] : non_negative)
    {
      if (!(value >= 0.0 && value <= 1e7))
      {
        errors.push_back(which + ": " + field + " = " + number(value) + ": must be in [0, 1e7]");
      }
    }
    if (attachment.mass >= 0.0 && std::abs(attachment.net_buoyancy) <= 1e7 &&
        attachment.net_buoyancy < -attachment.mass * CableLoading::kGravity)
    {
      // Its buoyancy is rho g V, its weight m g: net_buoyancy = rho g V - m g is never below -m g, its weight in air,
      // unless the volume it displaces is negative. Heavier in water than in air is no body (a clump given a weight
      // and no mass, say), and in air (above water_surface_z) it would weigh only m g.
      errors.push_back(which + ": net_buoyancy = " + number(attachment.net_buoyancy) +
                       " N: it weighs more in water than in air, mass x g = " + number(attachment.mass) + " kg x " +
                       number(CableLoading::kGravity) + " m/s^2 = " + number(attachment.mass * CableLoading::kGravity) +
                       " N (it would displace a negative volume): give its mass, at least " +
                       number(-attachment.net_buoyancy / CableLoading::kGravity) + " kg, or a smaller weight");
    }
    if (!(std::abs(attachment.net_buoyancy) <= 1e7))
    {
      errors.push_back(which + ": net_buoyancy = " + number(attachment.net_buoyancy) +
                       " N: must be finite, within +-1e7 N (up positive)");
    }
    else if (!made.materials().empty() && arc > 0.0 && arc <= params.cable_length && failsAtFullStrain(params.solver))
    {
      // Alone, a point load F stretches the cable it hangs on by F / EA. At F >= EA that is 100% or more: no cable
      // survives it (tethers break at a few per cent), and the solver takes a segment at kDivergenceLimit (100%)
      // for a blow-up. Above it a light attachment failed every step, the cable re-laid at rest each time (-1e7 N on
      // EA 1e5 N: 1000 re-lays in 5 s). EA is the smallest of the segments its particles join.
      const std::size_t segments = params.segmentCount();
      const auto k = static_cast<std::size_t>(std::floor(arc / params.segment_length));
      double stiffness = std::numeric_limits<double>::infinity();
      for (std::size_t j = k > 0 ? k - 1 : 0; j <= k + 1 && j < segments; ++j)
      {
        stiffness = std::min(stiffness, made.materials()[made.sectionOf(j)].axial_stiffness);
      }
      if (!(std::abs(attachment.net_buoyancy) < kDivergenceLimit * stiffness))
      {
        errors.push_back(
            which + ": net_buoyancy = " + number(attachment.net_buoyancy) +
            " N: its magnitude must be below the axial_stiffness of the cable it is on, EA = " + number(stiffness) +
            " N: alone it would stretch the cable by " + number(100.0 * std::abs(attachment.net_buoyancy) / stiffness) +
            "%, which no cable survives and the solver takes for a blow-up (a segment at 100% strain)");
      }
    }
    if (errors.size() == before)
    {
      loads.push_back(attachment);
    }
  }
  if (sections && failsAtFullStrain(params.solver))
  {
    // What the cable carries hanging, its attachments' loads with it (each refused for itself is said above).
    const std::vector<std::string> hanging = hangingLoadErrors(params, made, loads);
    errors.insert(errors.end(), hanging.begin(), hanging.end());
  }
  return errors;
}

void CableSections::load(const TetherParams& params, Cable* cable)
{
  CableLoading& loading = cable->loading;
  CableSections made;
  const Status status = make(params, params.sections, &made);
  const bool surface = !std::isnan(params.water_surface_z);
  if (!status)
  {
    // validate() (check()) refuses such a description before a tether is built or changed.
    throw std::invalid_argument(status.message);
  }
  if (made.uniform() && params.attachments.empty() && !surface)
  {
    loading = CableLoading{};  // a uniform cable: the parameters' own arithmetic
    return;
  }
  const std::size_t n = cable->size();
  const std::size_t segments = n - 1;
  loading.anisotropic = false;
  for (auto* v :
       {&loading.mass_along, &loading.mass_across, &loading.weight, &loading.normal_drag, &loading.tangential_drag,
        &loading.axial_stiffness, &loading.axial_damping, &loading.bending_stiffness})
  {
    v->assign(segments, 0.0);
  }
  for (auto* v : {&loading.point_mass, &loading.point_added, &loading.point_force, &loading.point_drag})
  {
    v->assign(n, 0.0);
  }
  // All under water until WaterSurface::update says otherwise (it runs before every sub-step).
  loading.submerged.assign(surface ? segments : 0, 1.0);
  loading.wet.assign(surface ? n : 0, 1.0);
  constexpr double kPi = 3.14159265358979323846;
  const double half_rho = 0.5 * params.water_density;
  const bool morison = params.drag_model == DragModel::kMorison;
  // Each section's values once (through the tether's own formulas), then each segment's.
  std::vector<std::array<double, 8>> values;
  for (const SectionMaterial& material : made.materials_)
  {
    TetherParams own = params;
    material.applyTo(&own);
    values.push_back({own.mass_per_length, own.effectiveMassPerLength(), own.weight_in_water,
                      half_rho * own.normal_drag_coefficient * own.diameter,
                      half_rho * own.tangential_drag_coefficient * kPi * own.diameter, own.axial_stiffness,
                      own.axial_damping, own.bending_stiffness});
  }
  for (std::size_t j = 0; j < segments; ++j)
  {
    const auto& v = values[made.sectionOf(segments - 1 - j)];
    loading.mass_along[j] = v[0], loading.mass_across[j] = v[1], loading.weight[j] = v[2];
    loading.normal_drag[j] = v[3], loading.tangential_drag[j] = v[4];
    loading.axial_stiffness[j] = v[5], loading.axial_damping[j] = v[6], loading.bending_stiffness[j] = v[7];
    loading.anisotropic = loading.anisotropic || v[0] != v[1];
  }
  for (const CableAttachment& attachment : params.attachments)
  {
    const Place place = placeOf(params, n, attachment);
    const auto add = [&](std::size_t particle, double share)
    {
      loading.point_mass[particle] += share * attachment.mass;
      // Added mass is Morison's, as the cable's own (none under the paper's damping).
      loading.point_added[particle] += morison ? share * attachment.added_mass : 0.0;
      loading.point_force[particle] += share * attachment.net_buoyancy;
      loading.point_drag[particle] += share * half_rho * attachment.drag_coefficient * attachment.drag_area;
    };
    add(place.near, 1.0 - place.far_share);
    if (place.far != place.near)
    {
      add(place.far, place.far_share);
    }
  }
}

CableSections::Place CableSections::placeOf(const TetherParams& params, std::size_t particles,
                                            const CableAttachment& attachment)
{
  // Particle particles - 1 is the vehicle end; s particles from it is arc length s * segment_length.
  const double last = static_cast<double>(particles - 1);
  const double s = std::min(attachment.arc_length_from_vehicle / params.segment_length, last);
  const double whole = std::floor(s);
  Place place;
  place.near = particles - 1 - static_cast<std::size_t>(whole);
  place.far_share = s - whole;
  place.far = place.far_share > 0.0 && place.near > 0 ? place.near - 1 : place.near;
  return place;
}

std::size_t CableSections::sectionOf(std::size_t k) const
{
  const auto it = std::upper_bound(ends_.begin(), ends_.end(), k);
  return it == ends_.end() ? ends_.size() - 1 : static_cast<std::size_t>(it - ends_.begin());
}

}  // namespace rov_tether
