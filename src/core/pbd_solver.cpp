#include <algorithm>
#include <cmath>

#include "rov_tether/constraint_solver.hpp"

// The hot loops are compiled twice (AVX2 and baseline x86-64) and the loader picks the clone the CPU
// supports, so one binary is fast on current machines and still runs on old ones.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(ROV_TETHER_NO_CLONES)
#define ROV_TETHER_TARGET_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ROV_TETHER_TARGET_CLONES
#endif

namespace rov_tether
{
namespace
{

/// Added to squared lengths before the division, far below any real length [m^2].
constexpr double kMinLengthSquared = 1e-24;

/**
 * Projects the distance constraints between particles a = start + kStride k and b = a + kSpan for
 * k in [0, count). Constraint data (rest, weight, lambda) is indexed by a. The constraints must share
 * no particle, which makes the loop free of dependencies between iterations.
 */
template <std::size_t kStride, std::size_t kSpan>
inline void projectSet(double* __restrict x, double* __restrict y, double* __restrict z,
                       const double* __restrict inv_mass, const double* __restrict rest,
                       const double* __restrict weight, double* __restrict lambda, std::size_t start,
                       std::size_t count)
{
  for (std::size_t k = 0; k < count; ++k)
  {
    const std::size_t a = start + kStride * k;
    const std::size_t b = a + kSpan;
    const double dx = x[b] - x[a];
    const double dy = y[b] - y[a];
    const double dz = z[b] - z[a];
    const double length_squared = dx * dx + dy * dy + dz * dz;
    // Branch-free so the loop vectorises; a zero-length constraint has d = 0 and so moves nothing.
    const double inv_length = 1.0 / std::sqrt(length_squared + kMinLengthSquared);
    // Correction factor: (|d| - rest) / |d| / (w_a + w_b); multiplier increment s |d| [kg m].
    const double s = (1.0 - rest[a] * inv_length) * weight[a];
    lambda[a] += s * length_squared * inv_length;
    const double move_a = inv_mass[a] * s;
    const double move_b = inv_mass[b] * s;
    x[a] += move_a * dx;
    y[a] += move_a * dy;
    z[a] += move_a * dz;
    x[b] -= move_b * dx;
    y[b] -= move_b * dy;
    z[b] -= move_b * dz;
  }
}

/// Number of indices start, start + stride, ... below end.
inline std::size_t countFrom(std::size_t start, std::size_t end, std::size_t stride)
{
  return start < end ? (end - start + stride - 1) / stride : 0;
}

void resetMultipliers(CableState& state, std::size_t segments_end, std::size_t bends_end)
{
  std::fill(state.stretch_lambda.begin() + static_cast<std::ptrdiff_t>(state.first),
            state.stretch_lambda.begin() + static_cast<std::ptrdiff_t>(segments_end), 0.0);
  if (bends_end > state.first)
  {
    std::fill(state.bend_lambda.begin() + static_cast<std::ptrdiff_t>(state.first),
              state.bend_lambda.begin() + static_cast<std::ptrdiff_t>(bends_end), 0.0);
  }
}

ROV_TETHER_TARGET_CLONES
void solveRedBlack(CableState& state, const SolverSettings& settings)
{
  const std::size_t n = state.size();
  const std::size_t f = state.first;
  if (n < f + 2)
  {
    return;
  }
  const std::size_t segments_end = n - 1;            // segments f .. n-2
  const std::size_t bends_end = n >= f + 3 ? n - 2 : f;  // bends f .. n-3
  resetMultipliers(state, segments_end, bends_end);

  double* x = state.x.data();
  double* y = state.y.data();
  double* z = state.z.data();
  const double* w = state.inv_mass.data();
  const double* rest = state.rest.data();
  const double* stretch_weight = state.stretch_weight.data();
  double* stretch_lambda = state.stretch_lambda.data();
  const double* bend_rest = state.bend_rest.data();
  const double* bend_weight = state.bend_weight.data();
  double* bend_lambda = state.bend_lambda.data();

  const std::size_t even = countFrom(f, segments_end, 2);
  const std::size_t odd = countFrom(f + 1, segments_end, 2);
  std::size_t bend_count[4];
  for (std::size_t r = 0; r < 4; ++r)
  {
    bend_count[r] = countFrom(f + r, bends_end, 4);
  }

  for (int iteration = 0; iteration < settings.iterations; ++iteration)
  {
    projectSet<2, 1>(x, y, z, w, rest, stretch_weight, stretch_lambda, f, even);
    projectSet<2, 1>(x, y, z, w, rest, stretch_weight, stretch_lambda, f + 1, odd);
    if (settings.bending)
    {
      // Sets 0 and 1 share no particle, nor do sets 2 and 3.
      for (std::size_t r = 0; r < 4; ++r)
      {
        projectSet<4, 2>(x, y, z, w, bend_rest, bend_weight, bend_lambda, f + r, bend_count[r]);
      }
    }
  }
}

}  // namespace

void PbdSolver::solve(CableState& state, const SolverSettings& settings)
{
  solveRedBlack(state, settings);
}

void SequentialPbdSolver::solve(CableState& state, const SolverSettings& settings)
{
  const std::size_t n = state.size();
  const std::size_t f = state.first;
  if (n < f + 2)
  {
    return;
  }
  const std::size_t segments_end = n - 1;
  const std::size_t bends_end = n >= f + 3 ? n - 2 : f;
  resetMultipliers(state, segments_end, bends_end);
  for (int iteration = 0; iteration < settings.iterations; ++iteration)
  {
    for (std::size_t j = f; j < segments_end; ++j)
    {
      projectSet<1, 1>(state.x.data(), state.y.data(), state.z.data(), state.inv_mass.data(), state.rest.data(),
                       state.stretch_weight.data(), state.stretch_lambda.data(), j, 1);
    }
    if (settings.bending)
    {
      for (std::size_t j = f; j < bends_end; ++j)
      {
        projectSet<1, 2>(state.x.data(), state.y.data(), state.z.data(), state.inv_mass.data(),
                         state.bend_rest.data(), state.bend_weight.data(), state.bend_lambda.data(), j, 1);
      }
    }
  }
}

std::unique_ptr<ConstraintSolver> makeSolver(SolverType type)
{
  if (type == SolverType::kPbdSequential)
  {
    return std::make_unique<SequentialPbdSolver>();
  }
  return std::make_unique<PbdSolver>();
}

}  // namespace rov_tether
