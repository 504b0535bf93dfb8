#include <algorithm>

#include "rov_tether/core/water.hpp"

namespace rov_tether
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
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
  for (std::size_t i = begin; i < end; ++i)
  {
    const Position x = cable.position(i);
    const Position previous(cable.px[i], cable.py[i], cable.pz[i]);
    const Position water = uniform ? u0 : current.at(x, t);
    const Position relative = (x - previous) / h - water;
    // Tangent from the neighbours' positions before this step (particle i - 1 already moved: its px).
    const Position behind(cable.px[i - 1], cable.py[i - 1], cable.pz[i - 1]);
    Position tangent = (i + 1 < n ? cable.position(i + 1) : x) - behind;
    const double tangent_length = tangent.norm();
    tangent = tangent_length > 0.0 ? Position(tangent / tangent_length) : Position::Zero();
    Position along = relative.dot(tangent) * tangent;
    Position across = relative - along;
    double sink_i = sink_across, sink_along_i = sink_along;
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
      along *= 1.0 - std::min(cable.inv_mass_along[i] * h * drag_along * along.norm(), 1.0);
      across *= 1.0 - std::min(cable.inv_mass[i] * h * drag_across * across.norm(), 1.0);
      const double weight = load.particleWeight(i, cable.rest, cable.first);
      sink_i = -weight * cable.inv_mass[i] * h * h;
      sink_along_i = -weight * cable.inv_mass_along[i] * h * h;
    }
    else
    {
      const double share = 0.5 * (cable.rest[i - 1] + (i + 1 < n ? cable.rest[i] : 0.0));
      const double h_per_mass = cable.inv_mass[i] * h * share;
      const double h_per_mass_along = cable.inv_mass_along[i] * h * share;
      along *= 1.0 - std::min(h_per_mass_along * tangential * along.norm(), 1.0);
      across *= 1.0 - std::min(h_per_mass * normal * across.norm(), 1.0);
    }
    Position next = x + (water + along + across) * h;
    // The weight: its share along the cable with the cable's mass, across with the added mass too.
    next.z() += sink_i;
    next += (sink_along_i - sink_i) * tangent.z() * tangent;
    cable.px[i] = x.x(), cable.py[i] = x.y(), cable.pz[i] = x.z();
    cable.x[i] = next.x(), cable.y[i] = next.y(), cable.z[i] = next.z();
  }
}

}  // namespace rov_tether
