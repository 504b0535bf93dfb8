#include "rov_tether/core/water.hpp"

namespace rov_tether
{
namespace
{

/// One axis of the damped Verlet update, paper eq. (6)-(8): x' = x + (x - x_prev) D + displacement.
void verletAxis(double* __restrict x, double* __restrict previous, std::size_t begin, std::size_t end, double damping,
                double displacement)
{
  for (std::size_t i = begin; i < end; ++i)
  {
    const double next = x[i] + (x[i] - previous[i]) * damping + displacement;
    previous[i] = x[i];
    x[i] = next;
  }
}

}  // namespace

void PaperDamping::integrate(Cable& cable, std::size_t begin, std::size_t end, double h, double t,
                             const TetherParams& params, const CurrentField& current) const
{
  // Net weight in water; a neutrally buoyant cable (the default) does no gravity work at all.
  const double sink = params.weight_in_water != 0.0 ? weightDisplacement(params, h) : 0.0;
  const double damping = params.dampingFactor(h);
  if (!cable.loading.empty())
  {
    // Sections and attachments: each particle's own weight over its own mass (the paper's drag is one
    // damping factor for every particle under water; above a water surface, none, and no current).
    const bool uniform = current.uniform();
    const Position& u0 = current.mean();
    for (std::size_t i = begin; i < end; ++i)
    {
      const double own = cable.loading.wetness(i) > 0.0 ? damping : 1.0;
      const Position drift = (1.0 - own) * h * (uniform ? u0 : current.at(cable.position(i), t));
      const double weight = cable.loading.particleWeight(i, cable.rest, cable.first);
      const double x = cable.x[i], y = cable.y[i], z = cable.z[i];
      cable.x[i] += (x - cable.px[i]) * own + drift.x();
      cable.y[i] += (y - cable.py[i]) * own + drift.y();
      cable.z[i] += (z - cable.pz[i]) * own + drift.z() - weight * cable.inv_mass[i] * h * h;
      cable.px[i] = x, cable.py[i] = y, cable.pz[i] = z;
    }
    return;
  }
  if (!current.uniform())
  {
    // Damping relative to the local water velocity: v' = u + D (v - u).
    for (std::size_t i = begin; i < end; ++i)
    {
      const Position drift = (1.0 - damping) * h * current.at(cable.position(i), t);
      const double x = cable.x[i], y = cable.y[i], z = cable.z[i];
      cable.x[i] += (x - cable.px[i]) * damping + drift.x();
      cable.y[i] += (y - cable.py[i]) * damping + drift.y();
      cable.z[i] += (z - cable.pz[i]) * damping + drift.z() + sink;
      cable.px[i] = x, cable.py[i] = y, cable.pz[i] = z;
    }
    return;
  }
  // A uniform current (zero by default) is one constant displacement per step.
  const double drift = (1.0 - damping) * h;
  verletAxis(cable.x.data(), cable.px.data(), begin, end, damping, drift * current.mean().x());
  verletAxis(cable.y.data(), cable.py.data(), begin, end, damping, drift * current.mean().y());
  verletAxis(cable.z.data(), cable.pz.data(), begin, end, damping, drift * current.mean().z() + sink);
}

std::unique_ptr<Drag> makeDrag(DragModel model)
{
  if (model == DragModel::kMorison)
  {
    return std::make_unique<MorisonDrag>();
  }
  return std::make_unique<PaperDamping>();
}

}  // namespace rov_tether
