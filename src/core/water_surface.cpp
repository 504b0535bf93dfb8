#include "rov_tether/core/water_surface.hpp"

#include <algorithm>

namespace rov_tether
{

double WaterSurface::submergedShare(double za, double zb, double surface)
{
  const double low = std::min(za, zb), high = std::max(za, zb);
  if (high <= surface)
  {
    return 1.0;
  }
  if (low >= surface)
  {
    return 0.0;
  }
  return (surface - low) / (high - low);  // high > low here
}

bool WaterSurface::update(Cable& cable, double surface, std::size_t* lo, std::size_t* hi)
{
  CableLoading& load = cable.loading;
  const std::size_t n = cable.size();
  std::size_t first_changed = n, last_changed = 0;
  const auto changed = [&](std::size_t a, std::size_t b)
  { first_changed = std::min(first_changed, a), last_changed = std::max(last_changed, b); };
  for (std::size_t j = cable.first; j + 1 < n; ++j)
  {
    const double share = submergedShare(cable.z[j], cable.z[j + 1], surface);
    if (share != load.submerged[j])
    {
      load.submerged[j] = share;
      if (load.mass_across[j] != load.mass_along[j])
      {
        changed(j, j + 1);  // its added mass
      }
    }
  }
  for (std::size_t i = cable.first; i < n; ++i)
  {
    const double wet = cable.z[i] <= surface ? 1.0 : 0.0;
    if (wet != load.wet[i])
    {
      load.wet[i] = wet;
      if (load.point_added[i] != 0.0)
      {
        changed(i, i);
      }
    }
  }
  *lo = first_changed, *hi = last_changed;
  return first_changed <= last_changed;
}

}  // namespace rov_tether
