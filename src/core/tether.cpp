#include "rov_tether/core/tether.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "cable_layout.hpp"
#include "rov_tether/core/cable_sections.hpp"
#include "rov_tether/core/direct_solver.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/water_surface.hpp"

namespace rov_tether
{
namespace
{

/// Whether a dynamic vehicle `body` can be coupled into the steps `params` take.
Status dynamicVehicleFits(const TetherParams& params, const VehicleBody& body)
{
  if (params.solver != SolverType::kDirect)
  {
    return Status::error("a dynamic vehicle is coupled into the step of solver 'direct' only; solver '" +
                         toString(params.solver) +
                         "' has no implicit step to couple it into (use a kinematic vehicle end, or solver direct)");
  }
  const double limit = body.stableStepLimitAt(params.water_surface_z);
  if (!(params.subStep() <= limit))
  {
    std::ostringstream out;
    out << "a dynamic vehicle needs sub-steps within its body's stable limit " << limit << " s"
        << (std::isnan(params.water_surface_z) ? "" : " (with the water surface: the hull's buoyancy and thrust)")
        << "; time_step / substeps is " << params.subStep() << " s";
    return Status::error(out.str());
  }
  return Status::success();
}

}  // namespace

bool Tether::withinLimits(const Position& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate; }

Tether::Tether(const TetherParams& params, const Position& spool, double start_time) : spool_(spool)
{
  const auto errors = params.validate();
  if (!errors.empty())
  {
    throw std::invalid_argument("invalid tether parameters: " + joinMessages(errors));
  }
  if (!withinLimits(spool) || !std::isfinite(start_time) || std::abs(start_time) > kMaxTime)
  {
    throw std::invalid_argument("spool position and start time must be finite (within +-1e6 m, +-1e10 s)");
  }
  time_ = target_time_ = base_time_ = start_time;
  applyParams(params);
  build(params_.initial_deployed_length);
}

Tether::Tether(const TetherParams& params, const Position& spool, const Position& vehicle, double start_time)
    : Tether(params, spool, start_time)
{
  if (!withinLimits(vehicle))
  {
    throw std::invalid_argument("vehicle position must be finite and within +-1e6 m");
  }
  track_.attachAt(start_time, vehicle);
  attachKinematic(vehicle);  // as when a first sample attaches: the cable reaches the vehicle
}

void Tether::applyParams(const TetherParams& requested)
{
  const TetherParams params = requested.resolved();
  const bool reseed = params.seed != params_.seed || !solver_;
  if (!solver_ || params.solver != params_.solver)
  {
    solver_ = makeSolver(params.solver);
  }
  if (!drag_ || params.drag_model != params_.drag_model)
  {
    drag_ = makeDrag(params.drag_model);
  }
  params_ = params;
  if (reseed)
  {
    noise_.reseed(params_.seed);
  }
  current_.configure(params_);
  spool_.setSegmentLength(params_.segment_length);
  contacts_.clear();
  seabed_.reset();
  if (!std::isnan(params_.seabed_z))
  {
    seabed_ = std::make_unique<SeabedContact>(params_.seabed_z, params_.seabed_friction);
    contacts_.push_back(seabed_.get());
  }
  if (world_contact_ != nullptr)
  {
    contacts_.push_back(world_contact_);
  }
  if (vehicle_ != nullptr)
  {
    vehicle_->setWaterSurface(params_.water_surface_z);  // a live change, seen before the next step
  }
}

void Tether::setWorldContact(Contact* contact)
{
  world_contact_ = contact;
  contacts_.erase(
      std::remove_if(contacts_.begin(), contacts_.end(), [&](const Contact* c) { return c != seabed_.get(); }),
      contacts_.end());
  if (contact != nullptr)
  {
    contacts_.push_back(contact);
  }
  substep_policy_.restart();
}

Position Tether::currentAt(const Position& point, double t) const { return current_.at(point, t); }

Status Tether::checkParams(const TetherParams& params) const
{
  const auto errors = params.validate();
  if (!errors.empty())
  {
    return Status::error("invalid tether parameters: " + joinMessages(errors));
  }
  if (vehicle_ != nullptr)
  {
    const Status coupled = dynamicVehicleFits(params.resolved(), vehicle_->body());
    if (!coupled)
    {
      return coupled;
    }
  }
  Status result = Status::success();
  if (!sameStructure(params_, params.resolved()))
  {
    result.message = "cable rebuilt for the new cable_length or segment_length at the deployed length";
  }
  if (vehicle_ != nullptr && params.water_density != params_.water_density)
  {
    // As when the vehicle was attached: it floats in the cable's water, or is said not to.
    const std::string water = waterMismatch(vehicle_->body().params(), params.water_density);
    result.message += water.empty() ? "" : (result.message.empty() ? "vehicle: " : "; vehicle: ") + water;
  }
  return result;
}

Status Tether::setParams(const TetherParams& params)
{
  const Status checked = checkParams(params);
  if (!checked.ok)
  {
    return checked;
  }
  const bool rebuild = !sameStructure(params_, params.resolved());
  const bool new_solver = params.solver != params_.solver;
  const bool new_mode = params.winch_mode != params_.winch_mode;
  const double old_step = params_.subStep();
  const double old_time_step = params_.time_step;
  const bool new_mass = params.resolved().lineMass().along != params_.lineMass().along ||
                        params.resolved().lineMass().across != params_.lineMass().across;
  // A rebuilt cable keeps its deployed length and, as when attaching, reaches the vehicle.
  const double deployed = track_.attached() ? lengthToReach(track_.position()) : deployedLength();
  applyParams(params);
  if (params_.winch_mode != WinchMode::kSpeed || params_.winch_speed == 0.0)
  {
    // A target lives in speed mode with a speed to go there at (setTargetLength); out of it, it is cleared.
    winch_.setTargetLength(std::numeric_limits<double>::quiet_NaN());
  }
  if (new_mode || new_solver)
  {
    // The new mode's (or the new method's) drive starts from the drum as it turns, but not from a slip past the old
    // drive (back-driven, it would pay out into slack): the one of the two nearer standing, and standing if they
    // turn opposite ways.
    winch_.restartDrive();
  }
  if (params_.time_step != old_time_step)
  {
    // Time is base_time_ + whole steps of time_step since base_steps_: counted from now in the new step (a rebuilt
    // cable's too). This is apart from the sub-step below: time_step and substeps may change together and keep
    // time_step / substeps.
    base_time_ = time_;
    base_steps_ = steps_;
  }
  if (rebuild)
  {
    noise_.reseed(params_.seed);
    build(std::clamp(deployed, params_.min_deployed_length, params_.cable_length));
    return checked;  // what was rebuilt
  }
  if (new_solver)
  {
    // The new method takes the cable as it is: same particles, same deployed length, no multipliers yet.
    solver_->multipliers().resize(cable_.size());
  }
  if (params_.subStep() != old_step)
  {
    // Keep each particle's velocity (x - x_prev) / h across the change of (sub-)step.
    const double ratio = params_.subStep() / old_step;
    for (std::size_t i = cable_.first; i < cable_.size(); ++i)
    {
      cable_.px[i] = cable_.x[i] - (cable_.x[i] - cable_.px[i]) * ratio;
      cable_.py[i] = cable_.y[i] - (cable_.y[i] - cable_.py[i]) * ratio;
      cable_.pz[i] = cable_.z[i] - (cable_.z[i] - cable_.pz[i]) * ratio;
    }
  }
  // Sections and attachments take the tether's values where they set none: any change may change them.
  const bool was_loaded = !cable_.loading.empty();
  CableSections::load(params_, &cable_);
  if (new_mass || was_loaded || !cable_.loading.empty())
  {
    refreshDerived(cable_.first, cable_.size() - 1);
  }
  return checked;  // success, with what checkParams says of the change (the vehicle's water)
}

void Tether::build(double deployed_length)
{
  cable_.resize(params_.segmentCount() + 1);
  CableSections::load(params_, &cable_);
  solver_->multipliers().resize(cable_.size());
  tension_scratch_.reserve(cable_.size());
  layOut(deployed_length);  // which has the contact forget the old cable (its record too, whatever its size)
}

void Tether::layOut(double deployed_length)
{
  ++lays_;
  if (world_contact_ != nullptr)
  {
    world_contact_->forget();
  }
  spool_.setDeployedLength(cable_, deployed_length);
  spool_placed_ = spool_.outlet();  // laid out at rest where the spool is
  CableLayout(params_).layOut(cable_, spool_.outlet(), track_.attached() ? &track_.position() : nullptr,
                              deployedLength());
  solver_->multipliers().clear();
  solver_->forget();
  refreshDerived(cable_.first, cable_.size() - 1);
  if (world_contact_ != nullptr)
  {
    // A cable laid out afresh (a vehicle attaching or jumping, a reset, a recovery) did not move there.
    // Measured from where the step began, the re-lay read as metres of motion, and the next step took the
    // most contact sub-steps (64) at once, stepping back down one a step. Over those steps a cable laid
    // taut at rest read 0 N at the spool and hundreds of newtons at the vehicle; the constant-tension winch
    // paid out at full speed from then on, and the cable it piled up wound onto itself (kilonewtons: issue
    // 26, a reset beside another tether; test Contact.ACableLaidOutAfreshIsNotMotion).
    step_motion_.start(cable_);
  }
}

void Tether::refreshDerived(std::size_t lo, std::size_t hi)
{
  cable_.updateMasses(lo, hi, params_.lineMass(), track_.attached());
}

Status Tether::setSpoolPosition(const Position& spool, bool jump)
{
  if (!withinLimits(spool))
  {
    return Status::error("spool position rejected: not finite or beyond +-1e6 m");
  }
  spool_.setOutlet(spool);
  if (jump)
  {
    layOut(track_.attached() ? lengthToReach(track_.position()) : deployedLength());  // places the outlet there
  }
  return Status::success();
}

Status Tether::setVehicleLoad(const Force& force, const Eigen::Vector3d& moment)
{
  if (vehicle_ == nullptr)
  {
    return Status::error("vehicle load rejected: the vehicle end is not dynamic");
  }
  return vehicle_->setLoad(force, moment);
}

Status Tether::addVehicleSample(double t, const Position& vehicle)
{
  if (vehicle_ != nullptr)
  {
    return Status::error(
        "vehicle sample rejected: the vehicle is dynamic (it moves by its own thrust and the tether's pull); "
        "detach it to drive the end by samples again");
  }
  if (!std::isfinite(t) || std::abs(t) > kMaxTime || !withinLimits(vehicle))
  {
    return Status::error(
        "vehicle sample rejected: time and position must be finite (time within +-1e10 s, "
        "position within +-1e6 m)");
  }
  return track_.add(t, vehicle, params_.max_vehicle_jump, params_.max_vehicle_speed, time_);
}

Status Tether::setTargetLength(double length)
{
  if (!std::isnan(length) && !(length >= params_.min_deployed_length && length <= params_.cable_length))
  {
    std::ostringstream out;
    out << "target length " << length << " m rejected: must be in [min_deployed_length, cable_length] = ["
        << params_.min_deployed_length << ", " << params_.cable_length << "] m";
    return Status::error(out.str());
  }
  if (!std::isnan(length) && !(params_.winch_mode == WinchMode::kSpeed && params_.winch_speed != 0.0))
  {
    // A target the winch would not go to (it acts in speed mode, at |winch_speed|) is refused, not kept and shown.
    std::ostringstream out;
    out << "target length " << length << " m rejected: a target is gone to in speed mode at |winch_speed|, and the "
        << "winch is in " << toString(params_.winch_mode) << " mode at winch_speed " << params_.winch_speed << " m/s";
    return Status::error(out.str());
  }
  winch_.setTargetLength(length);
  return Status::success();
}

void Tether::detachVehicle()
{
  vehicle_.reset();
  track_.detach();
  refreshDerived(cable_.size() - 3, cable_.size() - 1);
}

Position Tether::vehicleAt(double t)
{
  // The first sample's time has come: lay the cable out to it, or, when that was more than a sub-step ago
  // (1.5 of one: room for the rounding of step times), to where the vehicle is at t (laid to an old sample,
  // the end would be dragged the whole way in one step: 16,000 N in the pillar demo when the node started
  // late under load).
  if (track_.attachIfDue(t, 1.5 * params_.subStep()))
  {
    attachKinematic(track_.position());
  }
  if (!track_.attached())
  {
    return track_.position();
  }
  const VehicleTrack::Target target = track_.advance(t);
  if (target.jumped)
  {
    // The cable cannot follow a jump physically: re-lay it, at rest, to the new attachment point. One that lands
    // out of the cable's reach is said as a first position out of it is (attachKinematic).
    track_.setPosition(target.position);
    const std::string note = layOutToReach(target.position, "the vehicle's pose after a jump");
    ++jumps_;
    if (!note.empty())
    {
      ++out_of_reach_;
      last_out_of_reach_ = note + ": it jumped out of the tether's reach";
    }
  }
  return target.position;
}

double Tether::lengthToReach(const Position& vehicle) const
{
  if (params_.winch_mode == WinchMode::kLocked)
  {
    return deployedLength();
  }
  return std::clamp(std::max(deployedLength(), (vehicle - spool_.outlet()).norm()), params_.min_deployed_length,
                    params_.cable_length);
}

std::string Tether::layOutToReach(const Position& attachment, const char* who)
{
  const double laid = lengthToReach(attachment);
  layOut(laid);
  const double distance = (attachment - spool_.outlet()).norm();
  if (!(distance > laid))
  {
    return "";
  }
  // Out of the cable's reach (a locked winch, or all of it out): laid stretched to it, pulling hard at once.
  std::ostringstream out;
  out << who << " is " << distance << " m from the spool, beyond the " << laid << " m of cable "
      << (params_.winch_mode == WinchMode::kLocked ? "the locked winch has out" : "there is")
      << ": the cable is laid stretched to it (strain " << (distance - laid) / laid << ")";
  return out.str();
}

void Tether::attachKinematic(const Position& attachment)
{
  const std::string note = layOutToReach(attachment, "the vehicle's first position");
  if (!note.empty())
  {
    ++out_of_reach_;
    last_out_of_reach_ = note + ": its path starts out of the tether's reach";
  }
}

Status Tether::advance(double dt, std::size_t* steps)
{
  if (!std::isfinite(dt) || dt < 0.0)
  {
    std::ostringstream out;
    out << "advance rejected: interval " << dt << " s must be finite and >= 0";
    return Status::error(out.str());
  }
  return advanceTo(std::max(target_time_, time_) + dt, steps);
}

Status Tether::advanceTo(double t, std::size_t* steps)
{
  if (!std::isfinite(t) || std::abs(t) > kMaxTime)
  {
    return Status::error("advance rejected: target time must be finite and within +-1e10 s");
  }
  target_time_ = t;
  std::size_t taken = 0;
  while (stepFits(target_time_))
  {
    step();
    ++taken;
  }
  if (steps != nullptr)
  {
    *steps = taken;
  }
  return Status::success();
}

Status Tether::skipTo(double t)
{
  if (!std::isfinite(t) || std::abs(t) > kMaxTime || t < time_)
  {
    std::ostringstream out;
    out << "skip rejected: time " << t << " s must be finite and not before the simulation's " << time_ << " s";
    return Status::error(out.str());
  }
  for (std::size_t i = cable_.first; i < cable_.size(); ++i)
  {
    cable_.px[i] = cable_.x[i], cable_.py[i] = cable_.y[i], cable_.pz[i] = cable_.z[i];
  }
  if (vehicle_ != nullptr)
  {
    // A dynamic vehicle is not stepped while time is skipped: it keeps its pose and velocity.
    cable_.place(cable_.size() - 1, track_.position());
  }
  else if (track_.active())
  {
    track_.setPosition(vehicleAt(t));
    if (track_.attached())
    {
      cable_.place(cable_.size() - 1, track_.position());
    }
  }
  end_velocity_ = Velocity::Zero();
  time_ = target_time_ = base_time_ = t;
  base_steps_ = steps_;
  return Status::success();
}

void Tether::step()
{
  const double dt = params_.time_step;
  const double next_time = nextStepTime();
  const int substeps = world_contact_ != nullptr ? substep_policy_.substeps(params_.substeps) : params_.substeps;
  const double h = dt / substeps;
  const std::uint64_t failures = recoveries_;
  if (world_contact_ != nullptr)
  {
    step_motion_.start(cable_);
  }
  // A spool moved since the last step (setSpoolPosition) moves there in equal parts over the sub-steps.
  spool_step_ = (spool_.outlet() - spool_placed_) / substeps;
  for (int k = 1; k <= substeps && recoveries_ == failures; ++k)
  {
    spool_placed_ = k == substeps ? spool_.outlet() : Position(spool_placed_ + spool_step_);
    subStep(h, k == substeps ? next_time : next_time - dt + k * h, substeps - k);
  }
  spool_step_ = Position::Zero();
  last_step_ = h;
  substep_policy_.tookStep(substeps);
  if (world_contact_ != nullptr)
  {
    substep_policy_.plan(step_motion_.fastest(cable_), params_.diameter, params_.substeps);
  }
  ++steps_;
  time_ = next_time;
  if (recoveries_ == failures && !stateFinite())
  {
    fail("non-finite particle position");
  }
}

void Tether::subStep(double h, double t, int rest)
{
  const std::size_t n = cable_.size();
  cable_.placeMoving(cable_.first, spool_placed_, spool_step_);
  if (vehicle_ == nullptr && track_.active())
  {
    const bool was_attached = track_.attached();
    const Position before = track_.position();
    const std::uint64_t jumps = jumps_;
    track_.setPosition(vehicleAt(t));
    end_velocity_ = was_attached && jumps == jumps_ ? Velocity((track_.position() - before) / h) : Velocity::Zero();
  }
  std::size_t lo = 0, hi = 0;
  if (!std::isnan(params_.water_surface_z) && WaterSurface::update(cable_, params_.water_surface_z, &lo, &hi))
  {
    refreshDerived(lo, hi);  // the added mass of what crossed the surface
  }
  if (cable_.anisotropic)
  {
    cable_.updateTangents();  // the directions the added mass does not act in, fixed for the sub-step
  }
  if (cable_.first + 1 < freeEnd())
  {
    drag_->integrate(cable_, cable_.first + 1, freeEnd(), h, t, params_, current_);
  }
  // Every sub-step gets the noise of its own length, so the spread does not depend on `substeps`.
  noise_.apply(cable_, freeEnd(), params_.noiseAmplitude(h));
  if (vehicle_ != nullptr)
  {
    if (!predictVehicle(h, t))
    {
      return;
    }
  }
  else if (track_.attached())
  {
    // Its motion over the sub-step (none after a jump or a new attachment) in px: the last segment's
    // dashpot reads it.
    cable_.placeMoving(n - 1, track_.position(), end_velocity_ * h);
  }
  if (world_contact_ != nullptr)
  {
    world_contact_->takeReaction(cable_, cable_.first + 1, freeEnd(), h);
  }
  SolverSettings settings = SolverSettings::from(params_, h);
  settings.drum = winch_.beforeSolve(winchScene(), h);
  if (vehicle_ != nullptr)
  {
    // After the winch, which may re-weigh the particles near the spool (the whole chain when it is short).
    cable_.setInverseMass(n - 1, vehicle_inv_mass_);
  }
  solver_->solve(cable_, settings, contacts_, freeEnd());
  const std::string diverged = divergence(h);
  effort_.add(solver_->lastIterations(), solver_->lastResidual(), params_.solver_tolerance, solver_->lastRescued());
  effort_since_mark_.add(solver_->lastIterations(), solver_->lastResidual(), params_.solver_tolerance,
                         solver_->lastRescued());
  if (vehicle_ != nullptr && !finishVehicle(h, t, diverged, rest))
  {
    return;
  }
  if (world_contact_ != nullptr)
  {
    world_contact_->sendReaction();
    world_contact_->limitRebound(cable_, h);
    substep_policy_.sawPullIn(world_contact_->lastPullIn());
  }
  winch_.afterSolve(winchScene(), settings.drum != nullptr, h);
  if (!diverged.empty())
  {
    fail(diverged);
  }
}

std::string Tether::divergence(double h) const
{
  std::ostringstream why;
  const double strain = solver_->lastMaxStrain();
  if (!std::isnan(strain) && !(strain < kDivergenceLimit))
  {
    why << "lumped_mass diverged (segment strain " << strain << "): the sub-step " << h
        << " s exceeds the critical step " << params_.criticalStep()
        << " s = segment_length / sqrt(EA / mu) (shorter with axial_damping)";
    return why.str();
  }
  if (solver_->lastRescued() && !(solver_->lastRescueStrain() < kDivergenceLimit))
  {
    why << "direct solver diverged: after " << solver_->lastIterations()
        << " iterations (past `iterations`, to bring the step back) a segment ends at strain "
        << solver_->lastRescueStrain() << " (100% or more: a blow-up)";
    return why.str();
  }
  const double residual = solver_->lastResidual();
  if (!std::isnan(residual) && !(residual < kDivergenceLimit))
  {
    // A constraint still violated by its own length after `iterations` Newton steps and the rescue's more
    // (DirectSolver::kRescueBudget): the chain has folded (a teleport, a violent pull) and would not unfold by
    // itself.
    why << "direct solver did not converge (residual " << residual << " of a segment's length after "
        << solver_->lastIterations() << " iterations)";
  }
  return why.str();
}

void SolverEffort::add(int sub_step_iterations, double residual, double tolerance, bool rescue)
{
  rescued += rescue ? 1 : 0;
  if (residual > tolerance)
  {
    ++unconverged;
    unconverged_residual = residual;
    unconverged_iterations = sub_step_iterations;
  }
  if (sub_step_iterations >= 0)
  {
    ++substeps;
    iterations += static_cast<std::uint64_t>(sub_step_iterations);
    max_iterations = std::max(max_iterations, sub_step_iterations);
  }
  if (residual > max_residual)
  {
    max_residual = residual;
  }
}

bool Tether::predictVehicle(double h, double t)
{
  const std::size_t n = cable_.size();
  const Position attachment = track_.position();
  // The vehicle sits in the same water as the cable: the current at its attachment point.
  vehicle_->setCurrent(current_.at(attachment, t));
  const Status predicted = vehicle_->predict(h, &vehicle_predicted_);
  if (!predicted)
  {
    fail("dynamic vehicle: " + predicted.message);
    return false;
  }
  vehicle_inv_mass_ = vehicle_->inverseMass(cable_.position(n - 2), vehicle_predicted_, h);
  // The prediction, moving from where the attachment was (x - x_prev: its motion over the sub-step).
  cable_.place(n - 1, attachment);
  cable_.x[n - 1] = vehicle_predicted_.x();
  cable_.y[n - 1] = vehicle_predicted_.y();
  cable_.z[n - 1] = vehicle_predicted_.z();
  return true;
}

bool Tether::finishVehicle(double h, double t, const std::string& diverged, int rest)
{
  const std::size_t n = cable_.size();
  // The vehicle carries the last half segment's weight (a pinned particle's share, vehicleForce()); and the
  // tether's pull, which is what moved the attachment particle off its prediction in the solve:
  // M (x - x~) = h^2 F for the particle of mass 1 / w.
  Force pull = endLoad(n - 1, n - 2);
  std::string failed = diverged;
  if (failed.empty())
  {
    const Force solved = (cable_.position(n - 1) - vehicle_predicted_) / (h * h * vehicle_inv_mass_);
    if (solved.allFinite())
    {
      pull += solved;
    }
    else
    {
      failed = "direct solver: the solve left the vehicle's attachment point non-finite";
    }
  }
  cable_.setInverseMass(n - 1, 0.0);  // pinned again between sub-steps, as the kinematic end is
  Position reached;
  Status stepped = vehicle_->finish(h, pull, &reached);
  // A failed solve's particle moves are no force (the chain folded): the body steps without them, and over the
  // step's `rest` sub-steps too (each in the current where its attachment is then), which the tether skips to be
  // re-laid at rest to where the body ends.
  for (int k = 1; k <= rest && stepped && !failed.empty(); ++k)
  {
    vehicle_->setCurrent(current_.at(vehicle_->attachment(), t + k * h));
    stepped = vehicle_->finish(h, pull, &reached);
  }
  if (!stepped)
  {
    fail("dynamic vehicle: " + stepped.message + (failed.empty() ? "" : " (after: " + failed + ")"));
    return false;
  }
  cable_.x[n - 1] = reached.x(), cable_.y[n - 1] = reached.y(), cable_.z[n - 1] = reached.z();
  track_.setPosition(reached);
  if (diverged.empty() && !failed.empty())
  {
    fail(failed);  // the caller fails only what divergence() says
    return false;
  }
  return true;
}

Status Tether::attachVehicleBody(const VehicleBody& body, const Eigen::Vector3d& attachment_offset)
{
  const Status fits = dynamicVehicleFits(params_, body);
  if (!fits)
  {
    return fits;
  }
  if (!attachment_offset.allFinite() || attachment_offset.norm() > VehicleParams::kMaxOffset)
  {
    std::ostringstream out;
    out << "dynamic vehicle rejected: attachment_offset must be finite and within " << VehicleParams::kMaxOffset
        << " m of the body origin";
    return Status::error(out.str());
  }
  auto coupling = std::make_unique<VehicleCoupling>(body, attachment_offset);
  // The cable's water surface (above it the body floats less and is damped less), from the start and then as
  // applyParams changes it: a controller updated before a step reads the hull's wet share (its anti-windup).
  coupling->setWaterSurface(params_.water_surface_z);
  const Position attachment = coupling->attachment();
  if (!withinLimits(attachment))
  {
    return Status::error("dynamic vehicle rejected: its attachment point is not finite or beyond +-1e6 m");
  }
  vehicle_ = std::move(coupling);
  ++vehicle_starts_;
  track_.detach();
  track_.attachAt(time_, attachment);
  Status done = Status::success();
  // As when a first sample attaches: the cable reaches the vehicle, or is said not to; and the vehicle floats in
  // the cable's water, or is said not to (both warnings, the caller's to say).
  done.message = layOutToReach(attachment, "the vehicle's attachment");
  const std::string water = waterMismatch(body.params(), params_.water_density);
  done.message += water.empty() ? "" : (done.message.empty() ? "" : "; ") + water;
  return done;
}

Status Tether::setVehicleThrust(const Wrench& thrust)
{
  if (vehicle_ == nullptr)
  {
    return Status::error("vehicle thrust rejected: the vehicle end is kinematic (attachVehicleBody first)");
  }
  return vehicle_->setThrust(thrust);
}

void Tether::fail(const std::string& why)
{
  ++recoveries_;
  std::ostringstream message;
  // Fixed point: a ROS time of 1.8e9 s would otherwise print as 1.79565e+09, hiding the seconds.
  message << "t = " << std::fixed << std::setprecision(3) << time_ << " s: " << why
          << "; the cable was re-laid at rest";
  last_failure_ = message.str();
  winch_.restartDrive();  // as after a change of mode: not from a slip
  const double deployed = deployedLength();
  layOut(std::isfinite(deployed) ? std::clamp(deployed, params_.min_deployed_length, params_.cable_length)
                                 : params_.initial_deployed_length);
}

WinchDrive::Scene Tether::winchScene()
{
  return {cable_, spool_, params_, *solver_, track_.attached(), track_.position(), last_step_};
}

bool Tether::stateFinite() const
{
  double sum = 0.0;
  for (std::size_t i = cable_.first; i < cable_.size(); ++i)
  {
    sum += cable_.x[i] + cable_.y[i] + cable_.z[i];
  }
  return std::isfinite(sum);
}

Status Tether::reset(double time)
{
  if (!std::isfinite(time) || std::abs(time) > kMaxTime)
  {
    std::ostringstream out;
    out << "reset rejected: time " << time << " s must be finite and within +-" << kMaxTime << " s";
    return Status::error(out.str());
  }
  // Detached until the next sample: a replay after a reset starts exactly as the first run did.
  vehicle_.reset();
  track_.detach();
  winch_.reset();
  noise_.reseed(params_.seed);
  effort_ = SolverEffort{};
  effort_since_mark_ = SolverEffort{};
  time_ = target_time_ = base_time_ = time;
  base_steps_ = steps_;
  layOut(params_.initial_deployed_length);
  return Status::success();
}

double Tether::deployedLength() const { return spool_.deployedLength(cable_); }

void Tether::copyPositions(std::vector<Position>& out) const
{
  out.resize(deployedParticleCount());
  for (std::size_t k = 0; k < out.size(); ++k)
  {
    out[k] = particle(k);
  }
}

void Tether::computeSegmentTensions(std::vector<double>& out) const
{
  segmentTensions(cable_, solver_->multipliers(), last_step_, out);
}

bool Tether::segmentAtArcLengthFromVehicle(double arc_length, std::size_t* segment) const
{
  if (!std::isfinite(arc_length) || arc_length < 0.0 || arc_length > deployedLength())
  {
    return false;
  }
  // Every segment but the first (at the spool) has the nominal length.
  const std::size_t segments = deployedParticleCount() - 1;
  const double nominal = params_.segment_length;
  const double whole = std::floor(arc_length / nominal);
  *segment = whole >= static_cast<double>(segments - 1) ? 0 : segments - 1 - static_cast<std::size_t>(whole);
  return true;
}

double Tether::arcLengthFromVehicleToSegment(std::size_t k) const
{
  const std::size_t segments = deployedParticleCount() - 1;
  const double nominal = params_.segment_length;
  if (k == 0)
  {
    return static_cast<double>(segments - 1) * nominal + 0.5 * cable_.rest[cable_.first];
  }
  return (static_cast<double>(segments - 1 - k) + 0.5) * nominal;
}

double Tether::segmentStrain(std::size_t k) const { return cable_.strain(cable_.first + k); }

Force Tether::vehicleForce() const
{
  if (!track_.attached())
  {
    return Force::Zero();
  }
  if (vehicle_ != nullptr)
  {
    return vehicle_->pull();
  }
  const std::size_t n = cable_.size();
  if (last_step_ <= 0.0 || n < cable_.first + 2)
  {
    return Force::Zero();
  }
  return cannotPush(endForce(cable_, solver_->multipliers(), last_step_),
                    cable_.position(n - 2) - cable_.position(n - 1)) +
         endLoad(n - 1, n - 2);
}

Force Tether::spoolForce() const
{
  if (last_step_ <= 0.0 || deployedParticleCount() < 2)
  {
    return Force::Zero();
  }
  const std::size_t f = cable_.first;
  return cannotPush(startForce(cable_, solver_->multipliers(), last_step_),
                    cable_.position(f + 1) - cable_.position(f)) +
         endLoad(f, f);
}

Force Tether::cannotPush(const Force& pull, const Position& towards_cable)
{
  return pull.dot(towards_cable) > 0.0 ? pull : Force::Zero();
}

Force Tether::endLoad(std::size_t i, std::size_t j) const
{
  if (cable_.loading.empty())
  {
    return Force(0.0, 0.0, -0.5 * params_.weight_in_water * cable_.rest[j]);
  }
  return Force(0.0, 0.0, -0.5 * cable_.loading.segmentWeight(j) * cable_.rest[j] + cable_.loading.pointForce(i));
}

Status Tether::vehicleEndLinearisation(EndLinearisation* out, double horizon)
{
  if (!(horizon >= 0.0) || !std::isfinite(horizon))
  {
    return Status::error("end linearisation refused: horizon = " + std::to_string(horizon) +
                         " s: must be finite and >= 0 (0: the last step's own)");
  }
  if (!track_.attached())
  {
    return Status::error("end linearisation refused: no vehicle is attached (the last particle is a free end)");
  }
  if (vehicle_ != nullptr)
  {
    return Status::error(
        "end linearisation refused: the vehicle is dynamic, and VehicleCoupling already couples it inside the "
        "step; the linearisation is for a kinematic end driven by an external simulator");
  }
  auto* direct = params_.solver == SolverType::kDirect ? dynamic_cast<DirectSolver*>(solver_.get()) : nullptr;
  if (direct == nullptr)
  {
    return Status::error("end linearisation refused: solver '" + toString(params_.solver) +
                         "' has no implicit step to linearise; use solver 'direct'");
  }
  out->time = time_;
  out->position = track_.position();
  out->velocity = end_velocity_;
  out->force = vehicleForce();
  out->damping.setZero();  // no term in the end's velocity without axial damping; with it, not computed yet
  const SolverSettings settings = SolverSettings::from(params_, last_step_);
  out->horizon = std::max(horizon, settings.time_step);
  if (!direct->endStiffness(cable_, settings, horizon, &out->stiffness, &out->taut))
  {
    return Status::error("end linearisation failed: the last step's system is not positive definite");
  }
  return Status::success();
}

TetherSummary Tether::summary() const
{
  computeSegmentTensions(tension_scratch_);
  return summarize(tension_scratch_);
}

TetherSummary Tether::summarize(const std::vector<double>& tensions) const
{
  TetherSummary s = rov_tether::summarize(cable_, tensions, deployedLength(), time_);
  s.spool_force = spoolForce();
  s.vehicle_force = vehicleForce();
  return s;
}

}  // namespace rov_tether
