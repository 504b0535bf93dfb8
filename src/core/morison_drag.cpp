#include <algorithm>
#include <cmath>

#include "rov_tether/core/water.hpp"

namespace rov_tether
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

/// |v|^2 and a . b of 3-vectors, summed x, y, then z.
inline double norm2(const double* v) { return (v[0] * v[0] + v[1] * v[1]) + v[2] * v[2]; }
inline double dot(const double* a, const double* b) { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; }
}  // namespace

void MorisonDrag::integrate(Cable& cable, std::size_t begin, std::size_t end, double h, double t,
                            const TetherParams& params, const CurrentField& current) const
{
  // Morison drag on each particle's share of cable, split into the flow normal and tangential to the
  // cable. The impulse is explicit, h c |r| r, so a cable held against the flow feels exactly the drag,
  // but never more than stops the relative motion (r' = r (1 - min(h c |r| / m, 1))): stable at any step.
  // The added mass acts across the cable only, so the flow along it (and the weight's share along it)
  // moves the cable's own mass.
  const std::size_t n = cable.size();
  const double normal = 0.5 * params.water_density * params.normal_drag_coefficient * params.diameter;
  const double tangential = 0.5 * params.water_density * params.tangential_drag_coefficient * kPi * params.diameter;
  const LineMass mass = params.lineMass();
  const double sink_across = -params.weight_in_water / mass.across * h * h;
  const double sink_along = -params.weight_in_water / mass.along * h * h;
  const bool uniform = current.uniform();
  const CableLoading& load = cable.loading;
  const bool loaded = !load.empty();
  const Position& u0 = current.mean();
  // In scalars, each operation as the Eigen 3-vector expressions this was written with evaluated it (the same
  // roundings; norms and dot products summed x, y, then z): Eigen's small vectors cost 80% of a lumped_mass
  // step under the sanitizers.
  for (std::size_t i = begin; i < end; ++i)
  {
    const double x[3] = {cable.x[i], cable.y[i], cable.z[i]};
    double water[3] = {u0.x(), u0.y(), u0.z()};
    if (!uniform)
    {
      const Position flow = current.at(Position(x[0], x[1], x[2]), t);
      water[0] = flow.x(), water[1] = flow.y(), water[2] = flow.z();
    }
    const double relative[3] = {(x[0] - cable.px[i]) / h - water[0], (x[1] - cable.py[i]) / h - water[1],
                                (x[2] - cable.pz[i]) / h - water[2]};
    // Tangent from the neighbours' positions before this step (particle i - 1 already moved: its px).
    const double ahead[3] = {i + 1 < n ? cable.x[i + 1] : x[0], i + 1 < n ? cable.y[i + 1] : x[1],
                             i + 1 < n ? cable.z[i + 1] : x[2]};
    double tangent[3] = {ahead[0] - cable.px[i - 1], ahead[1] - cable.py[i - 1], ahead[2] - cable.pz[i - 1]};
    const double tangent_length = std::sqrt(norm2(tangent));
    for (double& c : tangent)
    {
      c = tangent_length > 0.0 ? c / tangent_length : 0.0;
    }
    const double projection = dot(relative, tangent);
    double along[3], across[3];
    for (std::size_t a = 0; a < 3; ++a)
    {
      along[a] = projection * tangent[a];
      across[a] = relative[a] - along[a];
    }
    double sink_i = sink_across, sink_along_i = sink_along;
    double keep_along = 0.0, keep_across = 0.0;
    if (loaded)
    {
      // Each neighbouring segment's half of its own drag and weight, and the attachments' (a body's drag
      // taken on both components of the flow).
      // Above a water surface: no drag (each half segment's share under water has it).
      const double left = load.submergedShare(i - 1) * cable.rest[i - 1];
      const double right = i + 1 < n ? load.submergedShare(i) * cable.rest[i] : 0.0;
      const double point_drag = load.wetness(i) * load.point_drag[i];
      const double drag_across =
          0.5 * (load.normal_drag[i - 1] * left + (i + 1 < n ? load.normal_drag[i] * right : 0.0)) + point_drag;
      const double drag_along =
          0.5 * (load.tangential_drag[i - 1] * left + (i + 1 < n ? load.tangential_drag[i] * right : 0.0)) + point_drag;
      keep_along = 1.0 - std::min(cable.inv_mass_along[i] * h * drag_along * std::sqrt(norm2(along)), 1.0);
      keep_across = 1.0 - std::min(cable.inv_mass[i] * h * drag_across * std::sqrt(norm2(across)), 1.0);
      const double weight = load.particleWeight(i, cable.rest, cable.first);
      sink_i = -weight * cable.inv_mass[i] * h * h;
      sink_along_i = -weight * cable.inv_mass_along[i] * h * h;
    }
    else
    {
      const double share = 0.5 * (cable.rest[i - 1] + (i + 1 < n ? cable.rest[i] : 0.0));
      const double h_per_mass = cable.inv_mass[i] * h * share;
      const double h_per_mass_along = cable.inv_mass_along[i] * h * share;
      keep_along = 1.0 - std::min(h_per_mass_along * tangential * std::sqrt(norm2(along)), 1.0);
      keep_across = 1.0 - std::min(h_per_mass * normal * std::sqrt(norm2(across)), 1.0);
    }
    // The weight: its share along the cable with the cable's mass, across with the added mass too.
    const double sink_tangent = (sink_along_i - sink_i) * tangent[2];
    double next[3];
    for (std::size_t a = 0; a < 3; ++a)
    {
      next[a] = x[a] + ((water[a] + along[a] * keep_along) + across[a] * keep_across) * h;
    }
    next[2] += sink_i;
    for (std::size_t a = 0; a < 3; ++a)
    {
      next[a] += sink_tangent * tangent[a];
    }
    cable.px[i] = x[0], cable.py[i] = x[1], cable.pz[i] = x[2];
    cable.x[i] = next[0], cable.y[i] = next[1], cable.z[i] = next[2];
  }
}

}  // namespace rov_tether
