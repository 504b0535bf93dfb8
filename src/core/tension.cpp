#include "rov_tether/core/tension.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{

void segmentTensions(const Cable& cable, const Multipliers& lambda, double step, std::vector<double>& out)
{
  const std::size_t n = cable.size();
  const std::size_t f = cable.first;
  out.assign(n - 1 - f, 0.0);
  if (step <= 0.0)
  {
    return;  // no step taken yet: no constraint force known
  }
  const double inv_dt2 = 1.0 / (step * step);
  for (std::size_t j = f; j + 1 < n; ++j)
  {
    // The force carried across the cut between particles j and j+1: the stretch constraint of segment j
    // and the bending constraints (j-1, j+1) and (j, j+2) that span the same cut.
    const Position axis = cable.direction(j, j + 1);
    Force carried = lambda.stretch[j] * axis;
    if (j > f && j + 1 < n)
    {
      carried += lambda.bend[j - 1] * cable.direction(j - 1, j + 1);
    }
    if (j + 2 < n)
    {
      carried += lambda.bend[j] * cable.direction(j, j + 2);
    }
    out[j - f] = carried.dot(axis) * inv_dt2;
  }
}

Force endForce(const Cable& cable, const Multipliers& lambda, double step)
{
  const std::size_t n = cable.size();
  if (step <= 0.0)
  {
    return Force::Zero();
  }
  // A stretched constraint (lambda > 0) pulls the vehicle back towards the cable.
  Force pull = -lambda.stretch[n - 2] * cable.direction(n - 2, n - 1);
  if (n >= cable.first + 3)
  {
    pull -= lambda.bend[n - 3] * cable.direction(n - 3, n - 1);
  }
  return pull / (step * step);
}

Force startForce(const Cable& cable, const Multipliers& lambda, double step)
{
  const std::size_t n = cable.size();
  const std::size_t f = cable.first;
  if (step <= 0.0 || f + 1 >= n)
  {
    return Force::Zero();
  }
  // A stretched constraint (lambda > 0) pulls the outlet towards the cable.
  Force pull = lambda.stretch[f] * cable.direction(f, f + 1);
  if (f + 2 < n)
  {
    pull += lambda.bend[f] * cable.direction(f, f + 2);
  }
  return pull / (step * step);
}

TetherSummary summarize(const Cable& cable, const std::vector<double>& tensions, double deployed_length, double time)
{
  TetherSummary result;
  result.time = time;
  result.deployed_length = deployed_length;
  if (tensions.empty())
  {
    return result;
  }
  result.tension_spool = tensions.front();
  result.tension_vehicle = tensions.back();
  const auto max_it = std::max_element(tensions.begin(), tensions.end());
  result.max_tension = *max_it;
  result.max_tension_segment = static_cast<std::size_t>(max_it - tensions.begin());
  double strain_sum = 0.0;
  result.max_strain = -1.0;
  for (std::size_t k = 0; k < tensions.size(); ++k)
  {
    const double strain = cable.strain(cable.first + k);
    result.max_strain = std::max(result.max_strain, strain);
    strain_sum += std::abs(strain);
  }
  result.mean_strain = strain_sum / static_cast<double>(tensions.size());
  return result;
}

}  // namespace rov_tether
