#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "rov_tether/core/cable.hpp"

namespace rov_tether
{

/**
 * How far a cable's particles moved over one step, what ContactSubstepPolicy cuts the next step by. The
 * noise's random walk and a pay-out's new particle are motion a contact must see and are counted; particles
 * paid out during the step (on the drum at its start) and the outlet (pinned, it jumps along the cable when
 * one is reeled in) are not.
 */
class StepMotion
{
 public:
  /// Takes the cable's positions now as where the step's motion is measured from. Allocates only the first
  /// time (the cable keeps its size from step to step).
  void start(const Cable& cable);
  /// How far the fastest free particle moved since start() [m]: infinite when one went to infinity; a NaN
  /// position is not counted (Tether::step finds it with stateFinite()).
  double fastest(const Cable& cable) const;

 private:
  std::vector<double> x_, y_, z_;  ///< Positions at the step's start [m].
  std::size_t first_ = 0;          ///< The spool outlet at the step's start.
};

/**
 * How many sub-steps a tether's step takes while a World contact is set (Tether::setWorldContact), from what
 * the step before saw. Two rules, and caps:
 * - motion: no particle moves more than kMotionShareOfRadius of the cable's radius in one sub-step, so a
 *   capsule cannot pass through another, or through an obstacle, between two sub-steps;
 * - depth: what a solve's tension pulls a particle into a contact within a sub-step (Contact::lastPullIn),
 *   which the contact then undoes, grows as h^2, so at n sub-steps instead of the `taken` it is
 *   (taken / n)^2 as deep; the count is raised until the deepest pull is predicted at kAimedPullInShare of
 *   the diameter, and lowered by one a step, only while the pull predicted for one fewer stays below that
 *   (so the count does not swing between two values: each swing changes h, and the tension's transient);
 * - never fewer than `substeps`; never more than kMaxSubsteps, nor than kDepthFactor times what the motion
 *   and `substeps` ask.
 * Tether asks substeps() before a step, and tells tookStep() after every step and plan() what a step with
 * contact saw.
 */
class ContactSubstepPolicy
{
 public:
  /// Largest share of the cable's radius a particle may move in one sub-step [-]. Below 1, so that two
  /// capsules of the cable's radius cannot pass each other between two sub-steps (contact, issue 14); the
  /// margin 0.8 dates from the contact's first version (75d5a9f), where the 2 m/s sweep past a 5 cm pole
  /// (Contact.NoTunnellingThroughAThinPoleAtTwoMetresASecond) does not tunnel.
  static constexpr double kMotionShareOfRadius = 0.8;
  /// The deepest pull-in aimed at, as a share of the diameter [-]: half of issue 14's bound on penetration
  /// (10% of the diameter).
  static constexpr double kAimedPullInShare = 0.05;
  /// Most sub-steps a step takes for contact [-]: a bound on the cost of one step (64 times `substeps` 1),
  /// reached by a particle moving 64 x 0.8 radii in a step, or by a re-laid cable read as motion.
  static constexpr int kMaxSubsteps = 64;
  /// The depth rule asks at most this many times what the motion and `substeps` ask [-]: a tension the
  /// vehicle keeps raising (a capstan of kilonewtons) would otherwise ask without end (1909cf6).
  static constexpr int kDepthFactor = 4;

  /// Sub-steps the next step with contact takes: `substeps` [-], or more when the last step asked for more.
  int substeps(int substeps) const { return std::max(substeps, next_); }
  /// Contact was set or removed: the next step takes `substeps` again.
  void restart() { next_ = 1; }
  /// A sub-step's solve pulled the cable `depth` [m] into a contact before the contact undid it.
  void sawPullIn(double depth) { deepest_ = std::max(deepest_, depth); }
  /// A step of `taken` sub-steps was taken (with contact or without).
  void tookStep(int taken) { last_ = taken; }
  /// After a step with contact, in which the fastest particle moved `motion` [m] (StepMotion::fastest) on a
  /// cable of `diameter` [m] with `substeps` configured: decides the next step's sub-steps from the rules
  /// above and starts the next step's pull-in afresh. A non-finite motion (a failed step) asks for none.
  void plan(double motion, double diameter, int substeps);

  /// Sub-steps the last step took [-].
  int lastSubsteps() const { return last_; }
  /// How far the fastest particle moved in the last step with contact [m] (0 when that was not finite).
  double lastMotion() const { return last_motion_; }

 private:
  /// The sub-steps the rules ask for after a step that moved `motion` [m] (see plan).
  int ask(double motion, double diameter, int substeps) const;

  int next_ = 1;  ///< Sub-steps the next step needs for contact.
  int last_ = 1;  ///< Sub-steps the last step took.
  double last_motion_ = 0.0;
  double deepest_ = 0.0;  ///< Largest pull-in of the step's sub-steps [m].
};

}  // namespace rov_tether
