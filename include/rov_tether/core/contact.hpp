#pragma once

#include <cstddef>
#include <vector>

#include "rov_tether/core/cable.hpp"

namespace rov_tether
{

/**
 * Something the cable cannot pass through, as a position constraint the solver projects. Contacts are
 * handed to the solver with the cable (ConstraintSolver::solve), so a method decides where in its
 * iterations they are projected; today every method projects them once after its sweeps. A contact may
 * keep state from one call to the next (what it touched, its friction holds, the reactions it owes): the
 * methods that change it are not const.
 */
class Contact
{
 public:
  virtual ~Contact() = default;
  /// Projects the free particles [begin, end) out of the obstacle, with the contact's friction unless it
  /// holds friction in the solve (holds()); must not allocate. `stretch` holds the step's multiplier of
  /// every segment (force = lambda / h^2), so a contact can tell how hard the cable pulls a particle into
  /// it. `first_pass`: the step's first projection (ConstraintSolver::solve may solve and project again).
  virtual void project(Cable& cable, std::size_t begin, std::size_t end, const std::vector<double>& stretch,
                       bool first_pass) = 0;
  /// Whether its friction is a force the solve balances (updateHold, applyHold, friction()), rather than a
  /// correction after the solve.
  virtual bool holds() const { return false; }
  /// After a solve: how far friction holds each touching particle back against its slip this step, given
  /// the cable as solved and its multipliers; `first` in the step's first pass. Returns whether a hold
  /// changed (then the step is solved again from the prediction moved by applyHold).
  virtual bool updateHold(const Cable& /*cable*/, const std::vector<double>& /*stretch*/, bool /*first*/)
  {
    return false;
  }
  /// Moves the predicted positions back by the holds.
  virtual void applyHold(Cable& /*cable*/) const {}
  /// Before the solve of a sub-step of `h` [s]: gives the free particles [begin, end) the change of velocity
  /// other bodies' contacts gave them since the last one (their reaction), and forgets it.
  virtual void takeReaction(Cable& /*cable*/, std::size_t /*begin*/, std::size_t /*end*/, double /*h*/) {}
  /// After a sub-step's solve: hands the reactions of its contacts on other bodies over to them.
  virtual void sendReaction() {}
  /// The cable was laid out anew (built anew for a parameter change, a reset, a vehicle that jumped or attached, a
  /// recovery): forgets what the contact kept of it (holds, pending reactions, and what it recorded touching, which
  /// belongs to the cable before, whatever its particle count).
  virtual void forget() {}
  /// Before a step's first solve: moves the predicted positions back by the holds of the last step (scaled
  /// to a step of `h` [s]), so a contact that sticks or slides as it did needs no further solve.
  virtual void warmStart(Cable& /*cable*/, double /*h*/) {}
  /// Friction as a correction after the solve, for a method that cannot solve again (lumped_mass).
  virtual void friction(Cable& /*cable*/, const std::vector<double>& /*stretch*/) {}
  /// After a sub-step of `h` [s]: limits how fast the contact sends a particle off (the velocity its
  /// push-out leaves in x - px), so an overlap older than the sub-step (a cable laid out through an
  /// obstacle) is undone in position without throwing the cable.
  virtual void limitRebound(Cable& /*cable*/, double /*h*/) const {}
  /// How far the solve's tension pulled a particle into the contact in the last step's first projection
  /// [m] (it grows as h^2); 0 when the contact does not say.
  virtual double lastPullIn() const { return 0.0; }
};

/// The contacts one solve sees (not owned: the tether and, later, the world own them).
using Contacts = std::vector<Contact*>;

/**
 * A flat seabed at height z with Coulomb friction: a particle below it is put back on it with no normal
 * velocity, and its sliding this step is limited to what the normal correction allows (position-based
 * friction, as Macklin et al. 2014 do for particles).
 */
class SeabedContact : public Contact
{
 public:
  SeabedContact(double z, double friction) : z_(z), friction_(friction) {}
  void project(Cable& cable, std::size_t begin, std::size_t end, const std::vector<double>& stretch,
               bool first_pass) override;

 private:
  double z_;
  double friction_;
};

}  // namespace rov_tether
