#include "rov_tether/core/spool.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{

double Spool::deployedLength(const Cable& cable) const
{
  const std::size_t n = cable.size();
  const std::size_t f = cable.first;
  return cable.rest[f] + static_cast<double>(n - 2 - f) * segment_;
}

void Spool::setDeployedLength(Cable& cable, double deployed) const
{
  const std::size_t n = cable.size();
  // Whole segments beyond the first; the first takes the remainder in [0.5, 1.5) segment lengths.
  const double whole = std::floor((deployed - kMinFirst * segment_) / segment_);
  const std::size_t count = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(whole, 0.0)) + 1, 1, n - 1);
  cable.first = n - 1 - count;
  std::fill(cable.rest.begin(), cable.rest.end(), segment_);
  cable.rest[cable.first] = deployed - static_cast<double>(count - 1) * segment_;
}

void Spool::payOut(Cable& cable, Multipliers& lambda, double change, const LineMass& mass_per_length, bool last_pinned,
                   bool rod_on_drum) const
{
  const std::size_t n = cable.size();
  cable.rest[cable.first] += change;
  if (change > 0.0)
  {
    while (cable.first > 0 && cable.rest[cable.first] > kMaxFirst * segment_ &&
           release(cable, lambda, change, mass_per_length, last_pinned, rod_on_drum))
    {
    }
  }
  else
  {
    while (cable.first + 2 < n && cable.rest[cable.first] < kMinFirst * segment_)
    {
      merge(cable, mass_per_length, last_pinned);
    }
  }
  cable.updateMasses(cable.first, cable.first + 2, mass_per_length, last_pinned);
}

bool Spool::release(Cable& cable, Multipliers& lambda, double change, const LineMass& mass_per_length, bool last_pinned,
                    bool rod_on_drum) const
{
  // Particle f leaves the spool: it is placed on the first segment, where the cable already is, with the
  // velocity of the cable material there, so neither the shape nor any constraint error changes and nothing
  // is jerked. The pinned outlet particle does not move, but the material passing it does: `change` along
  // the first segment in this step. The velocity is interpolated between that and particle f + 1's.
  const std::size_t f = cable.first;
  const double rest = cable.rest[f];
  double tx = cable.x[f + 1] - cable.x[f], ty = cable.y[f + 1] - cable.y[f], tz = cable.z[f + 1] - cable.z[f];
  const double length = std::sqrt(tx * tx + ty * ty + tz * tz);
  const bool slack_rod = rod_on_drum && length < rest;
  if (slack_rod && !(length > segment_))
  {
    return false;  // the slack stays in the first segment until it is long enough for a segment at rest
  }
  const double fraction = slack_rod ? (length - segment_) / length : (rest - segment_) / rest;
  const double scale = length > 0.0 ? change / length : 0.0;
  tx *= scale, ty *= scale, tz *= scale;
  auto along = [fraction, f](std::vector<double>& v, double from) { v[f] = from + fraction * (v[f + 1] - from); };
  along(cable.x, cable.x[f]), along(cable.y, cable.y[f]), along(cable.z, cable.z[f]);
  along(cable.px, cable.px[f] - tx), along(cable.py, cable.py[f] - ty), along(cable.pz, cable.pz[f] - tz);
  cable.first = f - 1;
  cable.place(cable.first, outlet_);
  cable.rest[cable.first] = rest - segment_;
  cable.rest[f] = segment_;
  lambda.stretch[cable.first] = lambda.stretch[f];  // both halves of the split segment carry its tension
  cable.updateMasses(cable.first, cable.first + 3, mass_per_length, last_pinned);
  return true;
}

void Spool::merge(Cable& cable, const LineMass& mass_per_length, bool last_pinned) const
{
  // The first free particle goes back onto the spool; its two segments become one with the summed
  // rest length, so the deployed length does not change.
  const std::size_t f = cable.first;
  cable.rest[f + 1] += cable.rest[f];
  cable.rest[f] = segment_;
  cable.first = f + 1;
  cable.place(f, outlet_);
  cable.place(cable.first, outlet_);
  cable.updateMasses(cable.first, cable.first + 2, mass_per_length, last_pinned);
}

}  // namespace rov_tether
