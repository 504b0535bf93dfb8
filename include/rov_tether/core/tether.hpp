#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/constraint_solver.hpp"
#include "rov_tether/core/contact.hpp"
#include "rov_tether/core/contact_substeps.hpp"
#include "rov_tether/core/current_field.hpp"
#include "rov_tether/core/end_linearisation.hpp"
#include "rov_tether/core/noise.hpp"
#include "rov_tether/core/spool.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/tension.hpp"
#include "rov_tether/core/tether_params.hpp"
#include "rov_tether/core/vehicle_coupling.hpp"
#include "rov_tether/core/vehicle_track.hpp"
#include "rov_tether/core/water.hpp"
#include "rov_tether/core/winch_drive.hpp"

namespace rov_tether
{

/// The Newton iterations and residuals a solver that stops on a tolerance (direct) took, summed over sub-steps.
struct SolverEffort
{
  std::uint64_t substeps = 0;    ///< Sub-steps that reported their iterations.
  std::uint64_t iterations = 0;  ///< Their iterations, summed.
  int max_iterations = -1;       ///< The most one took; -1: none reported.
  double max_residual = 0.0;     ///< The largest relative residual one stopped at [-].
  /// Sub-steps whose solve had diverged within `iterations` and went on past them
  /// (ConstraintSolver::lastRescued).
  std::uint64_t rescued = 0;
  /// Sub-steps that stopped with their residual above the solver's tolerance (`solver_tolerance`): at the
  /// iteration limit (the rescue's too), or on a system that was not definite. Their state is kept, and the
  /// tensions are those of an unconverged step.
  std::uint64_t unconverged = 0;
  /// The last of those: its residual [-] and iterations (NaN and -1 while there is none).
  double unconverged_residual = std::numeric_limits<double>::quiet_NaN();
  int unconverged_iterations = -1;
  /// Mean iterations per sub-step; NaN when none reported.
  double meanIterations() const
  {
    return substeps > 0 ? static_cast<double>(iterations) / static_cast<double>(substeps)
                        : std::numeric_limits<double>::quiet_NaN();
  }
  /// Adds a sub-step's `iterations` (negative: not reported, ignored) and `residual` (NaN: none), whether it
  /// was `rescued`, and counts it unconverged when its residual is above `tolerance`.
  void add(int iterations, double residual, double tolerance, bool rescue = false);
};

/**
 * The tether: a damped Verlet particle chain (paper eq. 6) with constraints, a spool and a vehicle end.
 * It composes the parts, each in its own file: the Cable (particle arrays), the VehicleTrack (samples,
 * interpolation, jumps), the Spool and a Winch mode, the water (Drag, CurrentField, weight,
 * MicroCurrentNoise), a ConstraintSolver with its multipliers and the Contacts it projects, and the tension
 * readout (tension.hpp). This class owns the order of a step and the recovery from failures.
 *
 * Time is plain seconds. The caller feeds vehicle positions with their times (addVehicleSample) and
 * advances by any interval; the simulation takes fixed internal steps of params().time_step and
 * interpolates the vehicle end linearly between samples. Invalid input is refused with a Status and
 * leaves the state untouched.
 */
class Tether
{
 public:
  /// A tether hanging from the spool with a free end. Throws std::invalid_argument on invalid params.
  Tether(const TetherParams& params, const Position& spool, double start_time = 0.0);
  /// A tether from the spool to a vehicle at `vehicle` at start_time, laid out at initial_deployed_length
  /// grown to the spool-vehicle distance unless the winch is locked. Throws std::invalid_argument.
  Tether(const TetherParams& params, const Position& spool, const Position& vehicle, double start_time = 0.0);

  /// Replaces the parameters between steps. `auto` values are resolved (params() returns the chosen ones). A change of
  /// cable_length or segment_length rebuilds the cable, at rest, at the deployed length (within the new limits, grown
  /// to reach the vehicle unless the winch is locked); other changes keep the state: a new solver takes the cable's
  /// particles and deployed length as they are, a new initial_deployed_length waits for reset(), a change of
  /// time_step keeps particle velocities. Invalid params are refused and the old ones kept.
  Status setParams(const TetherParams& params);
  /// What setParams(params) would return, changing nothing: the refusal, or success with the message it would give
  /// (the cable rebuilt), for a caller that says it before the change is made (Python's warning).
  Status checkParams(const TetherParams& params) const;
  const TetherParams& params() const { return params_; }

  /// Contact with what a World holds (obstacles, other tethers, itself), projected after the seabed; null
  /// for none. Not owned. While it is set, each step is cut into enough sub-steps (at least `substeps`)
  /// that no particle moves more than the cable's radius in one, judged from the last step's motion, so a
  /// capsule cannot pass through another or through an obstacle between two sub-steps, and more when a
  /// solve pulled the cable deep into a contact (ContactSubstepPolicy).
  void setWorldContact(Contact* contact);
  /// Sub-steps the last step took (`substeps`, or more for contact) [-].
  int lastSubsteps() const { return substep_policy_.lastSubsteps(); }
  /// How far the fastest particle moved in the last step, while a World contact is set [m].
  double lastMotion() const { return substep_policy_.lastMotion(); }

  /// Moves the spool outlet [m]. Refuses non-finite positions. The next step moves the outlet particle there
  /// in equal parts over its sub-steps, each placed moving by its part (the previous position in px), so the
  /// first segment's damping sees a spool that moves (a TMS's, World::mountSpool; a spool_frame's) as moving,
  /// not as jumping. With `jump` the spool did not travel there (its carrier started again elsewhere): the
  /// cable is re-laid at rest from the new outlet, to the vehicle (or hanging), as for a vehicle jump (not
  /// counted in jumpCount(), which counts the vehicle's).
  Status setSpoolPosition(const Position& spool, bool jump = false);
  /// Adds a vehicle attachment position [m] at time t [s]. Refuses non-finite values and times older
  /// than the last sample (a sample at the same time replaces it). The first sample attaches the vehicle
  /// when the simulation reaches its time (the cable is laid out to it then).
  /// A sample further from the previous one (dt earlier) than max_vehicle_speed * dt + max_vehicle_jump is a
  /// jump: the cable is re-laid, at rest, from the spool to the new position when the simulation reaches t
  /// (see README).
  /// At most VehicleTrack::kMaxSamples (4096) samples may wait ahead of the simulation; more are refused until it
  /// advances.
  Status addVehicleSample(double t, const Position& vehicle);
  /// In `speed` mode, pays out or reels in towards `length` [m] at |winch_speed| and holds it there.
  /// NaN clears the target. Refuses lengths outside [min_deployed_length, cable_length], and any target unless the
  /// winch is in speed mode with a winch_speed to go there at; parameters without either (setParams) clear it.
  Status setTargetLength(double length);
  /// The target length of `speed` mode [m], NaN when there is none.
  double targetLength() const { return winch_.targetLength(); }
  /// The winch's pay-out speed over the last (sub-)step [m/s], negative reeling in.
  double winchSpeed() const { return winch_.speed(); }
  /// True when the winch has paid out at max_winch_speed, the spool segment pulling harder than the winch
  /// gives way at (brake_tension, target_tension, strain: payout_threshold x EA), for every sub-step of the
  /// last kOutrunTime: the vehicle outruns the winch. One step at the limit (the jerk of a cable coming taut
  /// or slipping off a contact) is not an outrun.
  bool winchOutrun() const { return winch_.outrun(); }
  /// How long the winch must stay at its limit to be outrun [s].
  static constexpr double kOutrunTime = WinchDrive::kOutrunTime;
  /// True when a `speed` winch asked to reel in has been held back at the motor's stall pull
  /// (TetherParams::winchPull()) for kOutrunTime of sub-steps since it last reeled in at its commanded speed: it
  /// cannot reel in at its speed, as an outrun winch cannot pay out at the vehicle's. A few steps at the pull (a
  /// cable coming taut) are not.
  bool winchStalled() const { return winch_.stalled(); }
  /// True when a `speed` winch without a target length, its winch_speed asking to reel in, stood at
  /// min_deployed_length over the last step: it reels in no further (it slowed down to stop there at
  /// max_winch_acceleration), and the request goes unmet for as long as it stands (said once by the node and the
  /// runner).
  bool winchAtShortest() const { return winch_.atShortest(); }
  /// A `speed` winch's commanded speed in the last sub-step [m/s] (negative reeling in): winch_speed, or towards a
  /// target length; 0 in the other modes.
  double winchCommandedSpeed() const { return winch_.commandedSpeed(); }
  /// Detaches the vehicle (kinematic or dynamic): the last particle becomes a free end.
  void detachVehicle();
  bool vehicleAttached() const { return track_.attached(); }

  /// Attaches a dynamic vehicle, a copy of `body` as it is (pose, velocity, parameters), at the point
  /// `attachment_offset` [m] of its body frame: from now on the vehicle end is not driven by samples but moves
  /// as the body does under its thrust (setVehicleThrust), damping, restoring forces, the current at the
  /// attachment point and the tether's pull, solved within the step (VehicleCoupling,
  /// docs/model.md "A dynamic vehicle end"). The cable is laid out at rest to the attachment point as when a
  /// first sample attaches; vehicle samples are refused while it is dynamic. Only `direct` couples a vehicle
  /// into its step: with another solver, a sub-step beyond the body's stable limit in this tether's water
  /// (VehicleBody::stableStepLimitAt(water_surface_z)), a non-finite or
  /// too large offset (beyond VehicleParams::kMaxOffset) or an attachment point beyond kMaxCoordinate, it is
  /// refused and the tether is unchanged. detachVehicle() and reset() end it (the end is kinematic again).
  /// Attached, the status's message holds the warnings for the caller to say ("" for none): an attachment point
  /// out of the cable's reach, a vehicle whose water_density is not the tether's (waterMismatch), or both.
  Status attachVehicleBody(const VehicleBody& body, const Eigen::Vector3d& attachment_offset);
  /// The body-frame thrust command of the dynamic vehicle [N, N m], held until changed (saturated per axis
  /// at the body's thrust_limit). Refused without a dynamic vehicle or with non-finite values.
  Status setVehicleThrust(const Wrench& thrust);
  /// The dynamic vehicle's body (pose, velocity, parameters), or null while the vehicle end is kinematic.
  const VehicleBody* vehicleBody() const { return vehicle_ ? &vehicle_->body() : nullptr; }
  /// What the dynamic vehicle's last sub-step applied of its thrust command (within the limits, the axes held),
  /// or null while the vehicle end is kinematic.
  const ThrustUsed* vehicleThrustUsed() const { return vehicle_ ? &vehicle_->thrustUsed() : nullptr; }
  /// True while a dynamic vehicle is attached.
  bool vehicleDynamic() const { return vehicle_ != nullptr; }
  /// How many dynamic vehicles have been attached so far (attachVehicleBody): a new one after a reset is a
  /// vehicle that started again, not one that moved there.
  std::uint64_t vehicleStarts() const { return vehicle_starts_; }
  /// A load on the dynamic vehicle besides its tether's pull, held until changed: a world-frame force [N] and
  /// its moment about the body origin [N m] (VehicleCoupling::setLoad; a TMS carries the pull of the tether it
  /// pays out, World::mountSpool). Refused without a dynamic vehicle or with non-finite values.
  Status setVehicleLoad(const Force& force, const Eigen::Vector3d& moment);

  /// Advances by dt [s] (any value >= 0) in fixed internal steps; returns the number of steps taken
  /// through `steps` when given. Refuses negative or non-finite dt.
  Status advance(double dt, std::size_t* steps = nullptr);
  /// Advances until time() is within one internal step of t [s]. Refuses non-finite t.
  Status advanceTo(double t, std::size_t* steps = nullptr);
  /// Takes exactly one internal step.
  void step();
  /// Time the next internal step ends at [s].
  double nextStepTime() const { return base_time_ + static_cast<double>(steps_ + 1 - base_steps_) * params_.time_step; }
  /// True when one more internal step fits before t [s] (advanceTo takes steps while it does): its end,
  /// nextStepTime(), rounded as a caller that asks to stop there has it (time() + time_step rounds otherwise at a
  /// ROS time of 1.8e9 s, whose spacing is 2.4e-7 s: a step to its own end did not fit, half the time).
  bool stepFits(double t) const { return stepEndsBy(nextStepTime(), t, params_.time_step); }
  /// Whether a step of `step` [s] ending at `end` ends by `t` [s], to rounding: within a billionth of the step, or
  /// a few units of t's last place, whichever is more. At long times the step's end counted in steps from the base
  /// and t counted by the caller (an output time k / rate) differ by their rounding, which outgrows a billionth of
  /// a short step: 17,476,600 steps of 1 ms end 3.6e-12 s past 174,766 / 10 s, so that row held the step before.
  static bool stepEndsBy(double end, double t, double step)
  {
    return end <= t + std::max(1e-9 * step, 4.0 * std::numeric_limits<double>::epsilon() * std::abs(t));
  }
  /// Moves time forward to t [s] without stepping, for a caller that cannot keep up: the cable keeps its
  /// shape at rest, the vehicle end moves to where the samples put it at t. Refuses t before time().
  Status skipTo(double t);
  /// Re-lays the cable at initial_deployed_length, at rest, reseeds the noise and restarts time at
  /// `time` [s]. Vehicle samples are dropped and the vehicle is detached until the next sample, so a run
  /// after a reset repeats a fresh run exactly. Refuses times that are not finite or beyond kMaxTime.
  Status reset(double time);

  /// Largest |time| accepted [s] (1e10 s, 317 years): beyond it a step of 10 us no longer changes a
  /// double time by its own length.
  static constexpr double kMaxTime = 1e10;
  /// Largest |coordinate| of a spool or vehicle position accepted [m] (1000 km): beyond it constraint
  /// forces can overflow.
  static constexpr double kMaxCoordinate = 1e6;
  /// Whether every coordinate of p is finite and within kMaxCoordinate: where a spool, a vehicle or an attachment
  /// may be.
  static bool withinLimits(const Position& p);

  double time() const { return time_; }
  std::uint64_t stepCount() const { return steps_; }
  /// Deployed length: the sum of the deployed segments' rest lengths [m].
  double deployedLength() const;
  /// Deployed particles, spool outlet and vehicle (or free end) included.
  std::size_t deployedParticleCount() const { return cable_.size() - cable_.first; }
  /// Deployed particle k, k = 0 at the spool [m].
  Position particle(std::size_t k) const { return cable_.position(cable_.first + k); }
  /// Copies the deployed particles, spool first [m]. Reuses `out`'s capacity.
  void copyPositions(std::vector<Position>& out) const;
  /// Axial force of each deployed segment, spool first [N]: the constraint multipliers of the last step
  /// divided by dt^2 and summed with the bending constraints that cross the same cut (see README).
  void computeSegmentTensions(std::vector<double>& out) const;
  /// Geometric strain |d| / rest - 1 of deployed segment k [-].
  double segmentStrain(std::size_t k) const;
  /// Deployed segment (index from the spool) holding the point `arc_length` [m] from the vehicle end,
  /// measured along the rest lengths. Returns false for negative, non-finite or too long arc lengths.
  bool segmentAtArcLengthFromVehicle(double arc_length, std::size_t* segment) const;
  /// Arc length from the vehicle end to the middle of deployed segment k (k = 0 at the spool) [m].
  double arcLengthFromVehicleToSegment(std::size_t k) const;
  /// The force the vehicle receives at its attachment point [N], world frame; zero without a vehicle and
  /// before the first step: the last segment's pull, unless the segment is compressed (a cable cannot push:
  /// a pbd, xpbd or rod segment carrying compression gives nothing), plus the weight in water of the half
  /// segment lumped at the attachment particle, which the vehicle carries (a kinematic end's particle is
  /// pinned, so nothing else holds it up). With a dynamic vehicle, the force the last sub-step applied to the
  /// body (VehicleCoupling): the solve's pull and the same weight. Not included: that half segment's inertia
  /// and drag (m a with m = mass_per_length x dL / 2), and the last bending joint's force on the end (the
  /// joints of `direct` and `xpbd` carry no multiplier here).
  Force vehicleForce() const;
  /// The force the spool outlet receives from the cable [N], world frame, as vehicleForce(): the first
  /// segment's pull (none when it is compressed) plus the weight in water of the half segment lumped at the
  /// outlet; not the first bending joint's force on it. Zero before the first step.
  Force spoolForce() const;
  /// The pull on a kinematic vehicle end linearised in the end's position and velocity, for an external
  /// vehicle simulator (end_linearisation.hpp): F0 = vehicleForce(), K from the last `direct` step's own
  /// Newton system (a factorisation and three solves, on demand), C = 0 (derived there). Refused without
  /// a vehicle, with a dynamic one (VehicleCoupling couples it inside the step) and for solvers other than
  /// `direct`; an error too if the step's system is not positive definite (`out` then holds F0, K = C = 0).
  /// Allocation-free after the first call; the next step is the same whether it is called or not.
  /// `horizon` [s]: how long after the step the simulator applies it (0, or less than the sub-step h: the
  /// step's own K). A longer horizon linearises an implicit step of that length at the same state: the
  /// chain's inertia M / horizon^2 answers less, so K tends to the static stiffness (-EA / L_total along a
  /// taut chain). A simulator whose state runs `interpolation_delay` ahead of the physics needs that one: the
  /// step's K, twice as stiff on a 10 m chain at h = 5 ms, rings a 0.1 s loop. Refused when negative or NaN.
  Status vehicleEndLinearisation(EndLinearisation* out, double horizon = 0.0);
  /// Deployed length, end tensions, maximum tension and strain.
  TetherSummary summary() const;
  /// The same from segment tensions the caller already computed (computeSegmentTensions).
  TetherSummary summarize(const std::vector<double>& tensions) const;
  /// Iterations the solver took in the last sub-step when it stops on a tolerance (direct), else -1.
  int solverIterations() const { return solver_->lastIterations(); }
  /// The most iterations any sub-step took since construction or reset() (direct), else -1.
  int maxSolverIterations() const { return effort_.max_iterations; }
  /// What the solver took over every sub-step since construction or reset() (direct; none for the others).
  const SolverEffort& solverEffort() const { return effort_; }
  /// The same since the last markSolverEffort() (or construction, or reset()): what one row of output covers.
  const SolverEffort& solverEffortSinceMark() const { return effort_since_mark_; }
  /// Starts solverEffortSinceMark() afresh.
  void markSolverEffort() { effort_since_mark_ = SolverEffort{}; }
  /// Largest relative constraint residual the solver stopped at in the last sub-step (direct), else NaN.
  double solverResidual() const { return solver_->lastResidual(); }
  /// Number of vehicle jumps handled by re-laying the cable.
  std::uint64_t jumpCount() const { return jumps_; }
  /// Times the cable was laid out anew: at construction, and after a reset, a jump, a first pose out of reach, a
  /// recovery, a rebuild or a spool that jumped (RunOutWatch reads it).
  std::uint64_t layCount() const { return lays_; }
  /// Number of times a kinematic vehicle was attached (given at construction, or its first sample taken) beyond
  /// the cable's reach: further from the spool than the deployed length a locked winch keeps, or than
  /// cable_length. The cable is laid stretched to it, as attachVehicleBody does for a dynamic one (and says).
  std::uint64_t outOfReachCount() const { return out_of_reach_; }
  /// The last such attachment: the distance, the cable there is and the strain it is laid at ("" for none).
  const std::string& lastOutOfReach() const { return last_out_of_reach_; }
  /// Number of failures detected (a non-finite state, or a lumped_mass strain blow-up beyond its
  /// critical step) after which the cable was re-laid at rest; 0 in a healthy run.
  std::uint64_t recoveryCount() const { return recoveries_; }
  /// What the last failure was, when and why; empty when there was none.
  const std::string& lastFailure() const { return last_failure_; }
  /// Water velocity at `point` and time t [m/s]: the uniform current plus its slow variation.
  Position currentAt(const Position& point, double t) const;
  /// The particle arrays, for tests and converters.
  const Cable& state() const { return cable_; }
  /// The solver's multipliers of the last step (tension = lambda / h^2), for tests.
  const Multipliers& multipliers() const { return solver_->multipliers(); }

 private:
  void applyParams(const TetherParams& params);
  /// Sizes the cable for the parameters and lays it out at `deployed_length` [m].
  void build(double deployed_length);
  /// Gives the spool `deployed_length` [m] and lays the cable out at rest (CableLayout, src/core/cable_layout.hpp)
  /// from the spool to the vehicle; multipliers, masses and contact start afresh.
  void layOut(double deployed_length);
  /// Recomputes masses and weights of deployed particles [lo, hi] (Cable::updateMasses).
  void refreshDerived(std::size_t lo, std::size_t hi);
  /// One past the last free particle: the vehicle attachment is pinned.
  std::size_t freeEnd() const { return track_.attached() ? cable_.size() - 1 : cable_.size(); }
  Position vehicleAt(double t);
  /// Deployed length to lay the cable out with when the vehicle appears at `vehicle` (attach, jump):
  /// the current length, grown to the spool-vehicle distance unless the winch is locked [m].
  double lengthToReach(const Position& vehicle) const;
  /// Lays the cable out to a vehicle attaching at `attachment` (the deployed length that reaches it:
  /// lengthToReach); "" when the cable reaches it, else what `who` ("the vehicle's attachment", ...) meets: its
  /// distance from the spool, the cable there is, and the strain the cable is laid at.
  std::string layOutToReach(const Position& attachment, const char* who);
  /// A kinematic vehicle attaching at `attachment`: layOutToReach, an attachment out of reach counted and kept.
  void attachKinematic(const Position& attachment);
  /// One sub-step of h ending at t, `rest` more to come in this step (a dynamic vehicle steps over them alone
  /// when this one fails).
  void subStep(double h, double t, int rest);
  /// Why the last solve failed (a blow-up the tether is re-laid from), or "" when it did not.
  std::string divergence(double h) const;
  /// The dynamic vehicle's part of a sub-step of h at time t before the solve: the body's own step puts the
  /// attachment particle at its prediction, with the body's mobility as its inverse mass. False on failure.
  bool predictVehicle(double h, double t);
  /// After the solve of the sub-step of h ending at t: the body steps under the solved pull (else, when the solve
  /// `diverged` (why, as divergence() says it) or left the attachment point non-finite, under the last half
  /// segment's weight alone, and the step's `rest` sub-steps more); the attachment particle goes where it lands.
  /// False on failure (fail() called).
  bool finishVehicle(double h, double t, const std::string& diverged, int rest);
  void fail(const std::string& why);
  /// What the winch reads and moves in this sub-step.
  WinchDrive::Scene winchScene();
  bool stateFinite() const;

  TetherParams params_;
  Cable cable_;
  Spool spool_;
  VehicleTrack track_;
  std::unique_ptr<ConstraintSolver> solver_;
  std::unique_ptr<Drag> drag_;
  CurrentField current_;
  MicroCurrentNoise noise_;
  std::unique_ptr<SeabedContact> seabed_;  ///< None without seabed_z.
  Contacts contacts_;                      ///< What the solver projects besides the chain's constraints.
  Contact* world_contact_ = nullptr;       ///< World's contact for this tether; not owned.
  ContactSubstepPolicy substep_policy_;    ///< How many sub-steps a step with contact takes.
  StepMotion step_motion_;                 ///< Where the step's motion is measured from, with contact.
  WinchDrive winch_;                       ///< The winch: its mode's decisions, pay-out and drive.

  std::unique_ptr<VehicleCoupling> vehicle_;       ///< The dynamic vehicle, or none (kinematic end).
  Position vehicle_predicted_ = Position::Zero();  ///< The attachment particle's prediction in this sub-step [m].
  Position spool_placed_ = Position::Zero();       ///< Where the outlet particle was last placed [m].
  Position spool_step_ = Position::Zero();         ///< Its move per sub-step in this step, towards the outlet [m].
  std::uint64_t vehicle_starts_ = 0;               ///< Dynamic vehicles attached so far.
  double vehicle_inv_mass_ = 0.0;                  ///< Its inverse mass in this sub-step's solve [1/kg].
  /// The kinematic end's velocity over the last sub-step [m/s] (zero after an attach, a jump, a skip).
  Velocity end_velocity_ = Velocity::Zero();

  double time_ = 0.0;
  double target_time_ = 0.0;  ///< Time requested by the caller; time_ lags it by less than a step [s].
  double base_time_ = 0.0;    ///< Time of step number base_steps_; time_ = base + k dt avoids drift [s].
  std::uint64_t base_steps_ = 0;
  mutable std::vector<double> tension_scratch_;  ///< Reused by summary() so it does not allocate.
  /// What end particle `i` carries besides the tether's pull [N]: the weight in water of half of its
  /// deployed segment `j` (indices into the cable), and the buoyancy of an attachment's share on it.
  Force endLoad(std::size_t i, std::size_t j) const;
  /// `pull` when it pulls towards the cable (a positive component along `towards_cable`), else zero.
  static Force cannotPush(const Force& pull, const Position& towards_cable);
  double last_step_ = 0.0;  ///< Length of the last step taken [s] (tension = lambda / last_step^2).
  std::uint64_t steps_ = 0;
  std::uint64_t jumps_ = 0;
  std::uint64_t lays_ = 0;
  std::uint64_t out_of_reach_ = 0;
  std::string last_out_of_reach_;
  std::uint64_t recoveries_ = 0;
  SolverEffort effort_;
  SolverEffort effort_since_mark_;
  std::string last_failure_;
};

}  // namespace rov_tether
