#include "rov_tether/core/lumped_mass_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether
{

void LumpedMassSolver::project(Cable& state, Multipliers& lambda, const SolverSettings& settings)
{
  const std::size_t n = state.size();
  const std::size_t f = state.first;
  max_strain_ = 0.0;
  if (n < f + 2)
  {
    return;
  }
  const double h2 = settings.time_step * settings.time_step;
  const double ea = settings.axial_stiffness;
  // Kelvin-Voigt damping BA de/dt, on a slack segment too (a slack segment pulled straight pulls, as
  // MoorDyn's and direct's), its strain rate from the particles' predicted motion over the step (x - x_n: the
  // velocity after drag and weight, semi-implicit), read before this sweep moves them; the tension stays >= 0
  // (a cable does not push). The spool segment, whose rest length the winch changes before the step, is left
  // undamped (DirectWorkspace::begin).
  const double ba_over_h = settings.axial_damping / settings.time_step;
  double max_strain = -1.0;
  double strain_sum = 0.0;  // NaN or infinity anywhere makes the sum non-finite (max() would skip a NaN)
  // Forces at x_n (the previous positions px): explicit. The corrections go to the predictions x.
  Position moved(state.x[f] - state.px[f], state.y[f] - state.py[f], state.z[f] - state.pz[f]);  // particle j's
  for (std::size_t j = f; j + 1 < n; ++j)
  {
    const double dx = state.px[j + 1] - state.px[j];
    const double dy = state.py[j + 1] - state.py[j];
    const double dz = state.pz[j + 1] - state.pz[j];
    const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double strain = length / state.rest[j] - 1.0;
    max_strain = std::max(max_strain, strain);
    strain_sum += strain;
    const Position moved_next(state.x[j + 1] - state.px[j + 1], state.y[j + 1] - state.py[j + 1],
                              state.z[j + 1] - state.pz[j + 1]);
    double tension = ea * std::max(strain, 0.0);
    if (ba_over_h > 0.0 && length > 0.0 && j > f)  // the spool segment undamped, as direct's
    {
      // d(length)/dt h = n . (moved_next - moved), strain rate over 1 / rest.
      const double lengthening =
          ((moved_next.x() - moved.x()) * dx + (moved_next.y() - moved.y()) * dy + (moved_next.z() - moved.z()) * dz) /
          length;
      tension = std::max(tension + ba_over_h * lengthening / state.rest[j], 0.0);
    }
    moved = moved_next;
    lambda.stretch[j] = tension * h2;  // the same readout as the constraint methods: lambda / h^2
    const double scale = length > 0.0 ? tension * h2 / length : 0.0;
    const double move_a = state.inv_mass[j] * scale;
    const double move_b = state.inv_mass[j + 1] * scale;
    state.x[j] += move_a * dx;
    state.y[j] += move_a * dy;
    state.z[j] += move_a * dz;
    state.x[j + 1] -= move_b * dx;
    state.y[j + 1] -= move_b * dy;
    state.z[j + 1] -= move_b * dz;
    if (state.anisotropic)
    {
      // Along the cable only its own mass: the extra mobility (w_along - w_across) along the tangent.
      for (std::size_t i : {j, j + 1})
      {
        const double sign = i == j ? 1.0 : -1.0;
        const double extra = sign * (state.inv_mass_along[i] - state.inv_mass[i]) * scale *
                             (dx * state.tx[i] + dy * state.ty[i] + dz * state.tz[i]);
        state.x[i] += extra * state.tx[i];
        state.y[i] += extra * state.ty[i];
        state.z[i] += extra * state.tz[i];
      }
    }
  }
  if (n >= f + 3)
  {
    std::fill(lambda.bend.begin() + static_cast<std::ptrdiff_t>(f),
              lambda.bend.begin() + static_cast<std::ptrdiff_t>(n - 2), 0.0);
  }
  state.dirty_begin = state.dirty_end = 0;
  max_strain_ = std::isfinite(strain_sum) ? max_strain : std::numeric_limits<double>::infinity();
}

}  // namespace rov_tether
