#pragma once
// A flat water surface (water_surface_z, issue 22): which parts of a cable are in air.

#include <cstddef>

#include "rov_tether/core/cable.hpp"

namespace rov_tether
{

/**
 * Above a flat water surface a cable has no buoyancy (it weighs mass_per_length g), no drag and no added mass;
 * a segment that crosses it is split in proportion (CableLoading::submerged, wet).
 */
class WaterSurface
{
 public:
  /**
   * Sets `cable.loading`'s submerged share of each deployed segment (the length of it below z = surface, its
   * height linear between its ends) and the wetness of each deployed particle (1 at or below the surface, 0
   * above) from the positions now. The loading must have been made with a surface (CableSections::load).
   * Returns whether a mass changed, and then the particles whose did, [*lo, *hi], for Cable::updateMasses.
   */
  static bool update(Cable& cable, double surface, std::size_t* lo, std::size_t* hi);

  /// Share of the segment from height za to zb below z = surface [-].
  static double submergedShare(double za, double zb, double surface);
};

}  // namespace rov_tether
