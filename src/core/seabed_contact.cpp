#include <cmath>

#include "rov_tether/core/contact.hpp"

namespace rov_tether
{

void SeabedContact::project(Cable& cable, std::size_t begin, std::size_t end, const std::vector<double>& /*stretch*/,
                            bool /*first_pass*/)
{
  const double bed = z_;
  const double mu = friction_;
  for (std::size_t i = begin; i < end; ++i)
  {
    if (!(cable.z[i] < bed))
    {
      continue;
    }
    const double depth = bed - cable.z[i];
    cable.z[i] = bed;
    cable.pz[i] = bed;
    const double dx = cable.x[i] - cable.px[i];
    const double dy = cable.y[i] - cable.py[i];
    const double slide = std::sqrt(dx * dx + dy * dy);
    const double keep = slide > mu * depth ? 1.0 - mu * depth / slide : 0.0;
    cable.x[i] = cable.px[i] + keep * dx;
    cable.y[i] = cable.py[i] + keep * dy;
  }
}

}  // namespace rov_tether
