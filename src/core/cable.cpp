#include "rov_tether/core/cable.hpp"

#include <cmath>

namespace rov_tether
{

void Cable::resize(std::size_t particles)
{
  for (auto* v : {&x, &y, &z, &px, &py, &pz, &inv_mass, &inv_mass_along, &tx, &ty, &tz})
  {
    v->assign(particles, 0.0);
  }
  const std::size_t segments = particles > 0 ? particles - 1 : 0;
  for (auto* v : {&rest, &stretch_weight})
  {
    v->assign(segments, 0.0);
  }
  const std::size_t bends = particles > 1 ? particles - 2 : 0;
  for (auto* v : {&bend_rest, &bend_weight})
  {
    v->assign(bends, 0.0);
  }
  first = 0;
  loading = CableLoading{};
  markDirty(0, particles);
}

void Cable::place(std::size_t i, const Position& p)
{
  x[i] = px[i] = p.x();
  y[i] = py[i] = p.y();
  z[i] = pz[i] = p.z();
}

void Cable::placeMoving(std::size_t i, const Position& p, const Position& moved)
{
  place(i, p - moved);
  x[i] = p.x(), y[i] = p.y(), z[i] = p.z();
}

Position Cable::direction(std::size_t a, std::size_t b) const
{
  // In scalars (Eigen's small vectors are slow under the sanitizers), rounding as Eigen's norm() and division.
  const double d[3] = {x[b] - x[a], y[b] - y[a], z[b] - z[a]};
  const double length = std::sqrt((d[0] * d[0] + d[1] * d[1]) + d[2] * d[2]);
  return length > 0.0 ? Position(d[0] / length, d[1] / length, d[2] / length) : Position::Zero();
}

void Cable::updateMasses(std::size_t lo, std::size_t hi, const LineMass& mass_per_length, bool last_pinned)
{
  const bool loaded = !loading.empty();
  anisotropic = loaded ? loading.anisotropic : mass_per_length.along != mass_per_length.across;
  const std::size_t n = size();
  const std::size_t f = first;
  lo = std::max(lo, f);
  hi = std::min(hi, n - 1);
  // Bending constraints starting two particles before lo change too.
  markDirty(std::max(lo, f + 2) - 2, hi + 1);
  // Lumped masses: half of each neighbouring segment (a free end carries half a segment).
  for (std::size_t i = lo; i <= hi; ++i)
  {
    const double left = i > f ? rest[i - 1] : 0.0;
    const double right = i + 1 < n ? rest[i] : 0.0;
    const double length = 0.5 * (left + right);
    const bool pinned = i <= f || (last_pinned && i + 1 == n) || length <= 0.0;
    if (loaded)
    {
      // Each neighbouring segment's half of its own material, and the attachments' (added) mass in every
      // direction.
      const double across = 0.5 * ((i > f ? loading.segmentMassAcross(i - 1) * rest[i - 1] : 0.0) +
                                   (i + 1 < n ? loading.segmentMassAcross(i) * rest[i] : 0.0));
      const double point = loading.point_mass[i] + loading.wetness(i) * loading.point_added[i];
      const double along = 0.5 * ((i > f ? loading.mass_along[i - 1] * rest[i - 1] : 0.0) +
                                  (i + 1 < n ? loading.mass_along[i] * rest[i] : 0.0));
      inv_mass[i] = pinned ? 0.0 : 1.0 / (across + point);
      inv_mass_along[i] = pinned ? 0.0 : 1.0 / (along + point);
      continue;
    }
    inv_mass[i] = pinned ? 0.0 : 1.0 / (mass_per_length.across * length);
    inv_mass_along[i] = pinned ? 0.0 : 1.0 / (mass_per_length.along * length);
  }
  auto inverse_sum = [](double a, double b) { return a + b > 0.0 ? 1.0 / (a + b) : 0.0; };
  for (std::size_t j = std::max(lo, f + 1) - 1; j <= hi && j + 1 < n; ++j)
  {
    stretch_weight[j] = inverse_sum(inv_mass[j], inv_mass[j + 1]);
  }
  for (std::size_t j = std::max(lo, f + 2) - 2; j <= hi && j + 2 < n; ++j)
  {
    bend_rest[j] = rest[j] + rest[j + 1];
    bend_weight[j] = inverse_sum(inv_mass[j], inv_mass[j + 2]);
  }
}

void Cable::setInverseMass(std::size_t i, double w)
{
  inv_mass[i] = inv_mass_along[i] = w;
  auto inverse_sum = [](double a, double b) { return a + b > 0.0 ? 1.0 / (a + b) : 0.0; };
  const std::size_t n = size();
  for (std::size_t j = std::max(i, first + 1) - 1; j <= i && j + 1 < n; ++j)
  {
    stretch_weight[j] = inverse_sum(inv_mass[j], inv_mass[j + 1]);
  }
  for (std::size_t j = std::max(i, first + 2) - 2; j <= i && j + 2 < n; ++j)
  {
    bend_weight[j] = inverse_sum(inv_mass[j], inv_mass[j + 2]);
  }
  markDirty(std::max(i, first + 2) - 2, std::min(i + 1, n));
}

void Cable::updateTangents()
{
  const std::size_t n = size();
  for (std::size_t i = first; i < n; ++i)
  {
    const std::size_t a = i > first ? i - 1 : i;
    const std::size_t b = i + 1 < n ? i + 1 : i;
    const Position t = direction(a, b);
    tx[i] = t.x(), ty[i] = t.y(), tz[i] = t.z();
  }
}

}  // namespace rov_tether
