#include "rov_tether/core/constraint_solver.hpp"

#include <algorithm>

#include "rov_tether/core/direct_solver.hpp"
#include "rov_tether/core/lumped_mass_solver.hpp"
#include "rov_tether/core/pbd_solver.hpp"

namespace rov_tether
{

SolverSettings SolverSettings::from(const TetherParams& params, double h)
{
  SolverSettings settings;
  settings.iterations = params.iterations;
  settings.bending = params.bending;
  settings.time_step = h;
  settings.axial_stiffness = params.axial_stiffness;
  // A cable in sections: the largest damping and bending of any section switch them on (direct reads each
  // segment's own); a section that sets neither has the tether's.
  settings.axial_damping = params.largestOverSections("axial_damping", params.axial_damping);
  settings.bending_stiffness = params.largestBendingStiffness();
  settings.over_relaxation = params.over_relaxation;
  settings.tolerance = params.solver_tolerance;
  return settings;
}

void ConstraintSolver::solve(Cable& cable, const SolverSettings& settings, const Contacts& contacts,
                             std::size_t free_end)
{
  const std::size_t f = cable.first;
  rescued_ = false;
  rescue_strain_ = 0.0;
  bool passes = false;
  for (Contact* contact : contacts)
  {
    passes = passes || (contact->holds() && reprojects());
  }
  if (passes)
  {
    // The same size every step: no allocation once sized.
    predicted_x_.assign(cable.x.begin() + static_cast<std::ptrdiff_t>(f), cable.x.end());
    predicted_y_.assign(cable.y.begin() + static_cast<std::ptrdiff_t>(f), cable.y.end());
    predicted_z_.assign(cable.z.begin() + static_cast<std::ptrdiff_t>(f), cable.z.end());
    for (Contact* contact : contacts)
    {
      contact->warmStart(cable, settings.time_step);
    }
  }
  project(cable, multipliers_, settings);
  for (Contact* contact : contacts)
  {
    contact->project(cable, f + 1, free_end, multipliers_.stretch, true);
  }
  if (!passes)
  {
    for (Contact* contact : contacts)
    {
      contact->friction(cable, multipliers_.stretch);
    }
    return;
  }
  for (int pass = 1; pass <= kFrictionPasses; ++pass)
  {
    bool changed = false;
    for (Contact* contact : contacts)
    {
      changed = contact->updateHold(cable, multipliers_.stretch, pass == 1) || changed;
    }
    if (!changed)
    {
      break;
    }
    std::copy(predicted_x_.begin(), predicted_x_.end(), cable.x.begin() + static_cast<std::ptrdiff_t>(f));
    std::copy(predicted_y_.begin(), predicted_y_.end(), cable.y.begin() + static_cast<std::ptrdiff_t>(f));
    std::copy(predicted_z_.begin(), predicted_z_.end(), cable.z.begin() + static_cast<std::ptrdiff_t>(f));
    for (Contact* contact : contacts)
    {
      contact->applyHold(cable);
    }
    project(cable, multipliers_, settings);
    for (Contact* contact : contacts)
    {
      contact->project(cable, f + 1, free_end, multipliers_.stretch, false);
    }
  }
}

std::unique_ptr<ConstraintSolver> makeSolver(SolverType type)
{
  switch (type)
  {
    case SolverType::kPbdSequential:
      return std::make_unique<SequentialPbdSolver>();
    case SolverType::kXpbd:
      return std::make_unique<PbdSolver>(true);
    case SolverType::kLumpedMass:
      return std::make_unique<LumpedMassSolver>();
    case SolverType::kDirect:
      return std::make_unique<DirectSolver>();
    default:
      return std::make_unique<PbdSolver>();
  }
}

}  // namespace rov_tether
