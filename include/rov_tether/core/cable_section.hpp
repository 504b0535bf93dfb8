#pragma once
// What a tether's cable is made of along its length (issue 22), as written in its description: sections of
// their own material and point attachments (floats, clump weights). Plain data; CableSections checks it and
// turns it into the cable's per-segment loading.

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace rov_tether
{

/**
 * One stretch of a tether's cable with its own material, as MoorDyn and OrcaFlex describe a line: a `length`
 * and any of the per-metre parameters of the tether (CableSections::properties()), by their parameter names; a
 * property a section does not set is the tether's.
 */
struct CableSection
{
  /// Length of the section along the cable [m]; NaN for the last section only, which runs to the drum (what
  /// cable_length leaves of the sections before it).
  double length = std::numeric_limits<double>::quiet_NaN();
  /// The parameters this section sets, by name (a name of CableSections::properties(), at most once).
  std::vector<std::pair<std::string, double>> properties;

  bool operator==(const CableSection& other) const
  {
    return (length == other.length || (length != length && other.length != other.length)) &&
           properties == other.properties;
  }
};

/**
 * A point body clipped onto the cable at a material arc length from the vehicle end: a float (net_buoyancy > 0)
 * or a clump weight (< 0). It rides with its material through pay-out and reel-in.
 */
struct CableAttachment
{
  std::string name;
  double arc_length_from_vehicle = 0.0;  ///< Where it is clipped on, along the cable from the vehicle end [m].
  double mass = 0.0;                     ///< Its own mass [kg].
  double net_buoyancy = 0.0;             ///< Buoyancy minus weight in water [N], up positive.
  double added_mass = 0.0;               ///< The water it carries along, in every direction [kg].
  double drag_area = 0.0;                ///< Area facing the flow [m^2].
  double drag_coefficient = 1.0;         ///< Drag coefficient on drag_area [-].

  bool operator==(const CableAttachment& other) const
  {
    return name == other.name && arc_length_from_vehicle == other.arc_length_from_vehicle && mass == other.mass &&
           net_buoyancy == other.net_buoyancy && added_mass == other.added_mass && drag_area == other.drag_area &&
           drag_coefficient == other.drag_coefficient;
  }
};

}  // namespace rov_tether
