// The linearisation of the direct step's pull at a pinned last particle (direct_end_stiffness.hpp).
#include "direct_end_stiffness.hpp"

#include <algorithm>

namespace rov_tether
{

bool EndStiffness::compute(const Cable& cable, const Multipliers& multipliers, const SolverSettings& settings,
                           double horizon, Eigen::Matrix3d* stiffness, bool* taut)
{
  stiffness->setZero();
  *taut = false;
  const std::size_t f = cable.first;
  const std::size_t n = cable.size();
  // Sized on the first call whether the end pulls or not, so no later call allocates.
  workspace_.reserve(n);
  primal_.reserve(n);
  if (scratch_.stretch.size() != multipliers.stretch.size())
  {
    scratch_.resize(n);
  }
  if (columns_.size() < 9 * n)
  {
    columns_.assign(9 * n, 0.0);
  }
  if (scaled_.size() < n)
  {
    scaled_.assign(n, 0.0);
  }
  if (n < f + 2 || !(settings.time_step > 0.0))
  {
    return true;  // no segment, or no step taken since the cable was laid out: nothing pulls yet
  }
  if (cable.inv_mass[n - 1] != 0.0)
  {
    return false;  // an end that is not pinned (a dynamic vehicle) is not this linearisation's
  }
  const std::size_t m = n - 1 - f;
  // The step linearised is one of `step` [s]: the multipliers (force h^2) are carried over as the same forces.
  const double step = std::max(settings.time_step, horizon);
  const double carry = (step / settings.time_step) * (step / settings.time_step);
  for (std::size_t k = 0; k < m; ++k)
  {
    scaled_[k] = multipliers.stretch[f + k] * carry;
  }
  const double* lambda = scaled_.data();
  const double end_lambda = lambda[m - 1];
  if (!(end_lambda > 0.0))
  {
    return true;  // the last segment carries nothing (slack): nothing answers a small move of the end
  }
  *taut = true;
  const std::size_t rows = 3 * (m + 1);
  // The step's system as its last Newton iteration sees it, at the step's solution: the geometry of the
  // positions now, the multipliers the step ended with, the segments that carry them (all of a rod's). The
  // spool segment is taken by its elastic law (a drum giving way within the step is left out).
  SolverSettings elastic = settings;
  elastic.drum = nullptr;
  elastic.time_step = step;
  elastic.axial_damping = 0.0;  // K is the elastic answer; the damping is a force on velocity, not position
  DirectWorkspace& ws = workspace_;
  ws.begin(cable, scratch_, elastic);
  double* model = ws.on();
  for (std::size_t k = 0; k < m; ++k)
  {
    model[k] = !ws.unilateral || lambda[k] > 0.0 ? 1.0 : 0.0;
  }
  // B: the last segment's Hessian block, axial 1 / alpha along n and the geometric stiffness lambda / |d|
  // across it (as PrimalNewton::assemble's segmentTerms; lambda > 0 here).
  const Eigen::Vector3d along(ws.nx[m - 1], ws.ny[m - 1], ws.nz[m - 1]);
  const double axial = 1.0 / ws.alpha[m - 1];
  const double geometric = ws.len[m - 1] > 0.0 ? end_lambda / ws.len[m - 1] : 0.0;
  const Eigen::Matrix3d block =
      (axial - geometric) * along * along.transpose() + geometric * Eigen::Matrix3d::Identity();
  // H_fe: how the free particles' equations depend on the end: particle m - 1 through the last segment
  // (-B) and, with bending, both through the last joint (the curvature's weights g, a x_m-2 - (a + b) x_m-1
  // + b x_m, each pair coupled by g_r g_s / gamma).
  Eigen::Matrix3d coupling_last = -block;
  double coupling_before = 0.0;  // times the identity
  if (ws.bending && m >= 2)
  {
    const double a = ws.inv_rest[m - 2];
    const double b = ws.inv_rest[m - 1];
    const double inv = ws.inv_gamma[m - 2];
    coupling_last += -(a + b) * b * inv * Eigen::Matrix3d::Identity();
    coupling_before = a * b * inv;
  }
  std::fill(columns_.begin(), columns_.begin() + static_cast<std::ptrdiff_t>(3 * rows), 0.0);
  const bool last_free = cable.inv_mass[f + m - 1] > 0.0;
  const bool before_free = m >= 2 && cable.inv_mass[f + m - 2] > 0.0;
  for (std::size_t c = 0; c < 3; ++c)
  {
    double* column = &columns_[c * rows];
    for (std::size_t r = 0; r < 3 && last_free; ++r)
    {
      column[3 * (m - 1) + r] = -coupling_last(r, c);
    }
    if (before_free)
    {
      column[3 * (m - 2) + c] = -coupling_before;
    }
  }
  if (!primal_.solveHessian(cable, lambda, columns_.data(), 3))
  {
    stiffness->setZero();
    *taut = false;
    return false;
  }
  // Y: the last free particle's answer dx_m-1 / dx_e; F = -dE/dx_e / h^2 moves by -(B - B Y) dx_e / h^2.
  Eigen::Matrix3d answer;
  for (std::size_t c = 0; c < 3; ++c)
  {
    for (std::size_t r = 0; r < 3; ++r)
    {
      answer(r, c) = columns_[c * rows + 3 * (m - 1) + r];
    }
  }
  const double h2 = step * step;
  *stiffness = -(block - block * answer) / h2;
  return true;
}

}  // namespace rov_tether
