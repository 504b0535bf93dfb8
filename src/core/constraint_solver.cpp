#include "rov_tether/constraint_solver.hpp"

#include "rov_tether/direct_solver.hpp"
#include "rov_tether/lumped_mass_solver.hpp"
#include "rov_tether/pbd_solver.hpp"

namespace rov_tether
{

SolverSettings SolverSettings::from(const TetherParams& params, double h)
{
  SolverSettings settings;
  settings.iterations = params.iterations;
  settings.bending = params.bending;
  settings.time_step = h;
  settings.axial_stiffness = params.axial_stiffness;
  settings.bending_stiffness = params.bending_stiffness;
  settings.over_relaxation = params.over_relaxation;
  settings.tolerance = params.solver_tolerance;
  return settings;
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
