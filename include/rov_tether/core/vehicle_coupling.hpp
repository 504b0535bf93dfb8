#pragma once
// A dynamic vehicle at a tether's end: its VehicleBody coupled into the `direct` solver's implicit step
// (docs/model.md, "A dynamic vehicle end").

#include <Eigen/Geometry>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/vehicle_body.hpp"

namespace rov_tether
{

/**
 * The vehicle end of a tether when the vehicle is dynamic: the chain's last particle is the attachment point
 * (the body's origin plus R `offset`), not pinned, and moves as the vehicle does. One sub-step of h:
 *
 *  1. predict(): the body takes a step under its own forces alone (thrust, damping, restoring, Coriolis,
 *     current; no tether): the attachment point lands at x~, the last particle's prediction;
 *  2. inverseMass(): the attachment point's mobility along the last segment, w = n^T W_p n with
 *     W_p = R G (M + h D)^-1 G^T R^T, G = [I, -S(offset)] (body frame): how far a pull of 1 N along the
 *     tether moves that point in the body's own step, per h^2. It holds the body's mass and added mass
 *     (6x6, so an offset attachment's turning too) and its damping, which the body's step takes implicitly.
 *     The solver sees the vehicle as that one scalar mass: exact for a pull along the last segment at the
 *     start of the step, which is what a taut tether gives (the correction J^T lambda is along it); the
 *     sideways motion the pull also causes (W_p n off n) is not in the solve but in step 4;
 *  3. the solver solves the chain with the last particle of inverse mass w at x~; the tether's pull on the
 *     vehicle is what moved it off its prediction: F = (x - x~) / (h^2 w), from the same solve, so a taut
 *     tether holds a thrusting vehicle with the force the step's end needs, not the last step's;
 *  4. finish(): the body takes predict()'s step again, now with F at the attachment point besides (the force
 *     and its moment offset x F: semi-implicit, F fixed from the solve; VehicleBody::stepAgain, which reuses
 *     the prediction's work), and the last particle is put at the attachment point it reaches. Along the
 *     tether the two agree (step 2); they differ by the sideways motion and the turn of the step, which the
 *     next step's solve sees as a new position.
 * Steps 1, 2 and 4 share one factorisation of M + h D (the same start, the same damping), and step 4 starts
 * its Coriolis part from the prediction's: one body step and one Coriolis pass a sub-step (docs/benchmarks.md,
 * "A dynamic vehicle end"). No allocation (fixed-size Eigen only).
 */
class VehicleCoupling
{
 public:
  /// Takes `body` (its pose and velocity as they are) with the attachment `offset` in the body frame [m].
  VehicleCoupling(const VehicleBody& body, const Eigen::Vector3d& offset);

  const VehicleBody& body() const { return body_; }
  const Eigen::Vector3d& offset() const { return offset_; }
  /// Where the attachment point is now, world frame [m].
  Position attachment() const { return body_.position() + body_.attitude() * offset_; }

  /// Sets the body-frame thrust command [N, N m], held until changed; saturated per axis by the body.
  /// Refuses non-finite values.
  Status setThrust(const Wrench& thrust);
  const Wrench& thrust() const { return thrust_; }
  /// What the last step applied (the command within the limits) and which axes were held.
  const ThrustUsed& thrustUsed() const { return used_; }

  /// A load besides the tether's, held until changed: the world-frame force [N] and its moment about the body
  /// origin [N m] (a TMS carries the pull of the tether its winch pays out: World::mountSpool). The body feels
  /// it in every step from the next one on, turned into its frame at each step's start. Refuses non-finite
  /// values.
  Status setLoad(const Force& force, const Eigen::Vector3d& moment);

  /// The current at the attachment point [m/s], world frame, for the body's next steps (finite: the tether's
  /// own current field).
  void setCurrent(const Eigen::Vector3d& current)
  {
    (void)body_.setCurrent(current);
    started_ = false;
  }
  /// The water surface's height [m] (NaN: none): VehicleBody::setWaterSurface.
  void setWaterSurface(double z)
  {
    body_.setWaterSurface(z);
    started_ = false;
  }
  /// Step 1: the attachment point after a step of h [s] under the body's own forces alone. Refuses a step
  /// beyond the body's stable limit; the body is unchanged.
  Status predict(double h, Position* predicted);
  /// Step 2: the inverse mass [1/kg] the solver gives the last particle, the attachment point's mobility
  /// along the direction from `neighbour` (the last-but-one particle's prediction) to `predicted`; the
  /// largest eigenvalue of W_p when the two coincide. Without predict(h) the body's step of h is factored here as
  /// predict() would (0 for a step the body refuses).
  double inverseMass(const Position& neighbour, const Position& predicted, double h) const;
  /// Step 4: the body's step of h under the tether's pull `pull` (world frame, at the attachment point)
  /// besides its own forces. Returns the attachment point it reaches.
  Status finish(double h, const Force& pull, Position* attachment);
  /// The pull of the last finish() [N], world frame.
  const Force& pull() const { return pull_; }

 private:
  /// The attachment point's 3x3 mobility W_p in the body frame for the step `start` prepares [1/kg].
  Eigen::Matrix3d pointMobility(const VehicleStepStart& start) const;

  VehicleBody body_;  ///< At the sub-step's start until finish() (predict() leaves it).
  /// The sub-step's start, prepared by predict() and shared by inverseMass() and finish() (valid while started_:
  /// the body unchanged since).
  VehicleStepStart start_;
  VehicleStepTrial trial_;  ///< predict()'s step, taken again with the pull by finish()
  bool started_ = false;
  Eigen::Vector3d offset_;
  Wrench thrust_ = Wrench::Zero();
  ThrustUsed used_;
  Force pull_ = Force::Zero();
  Force load_force_ = Force::Zero();                       ///< setLoad's force, world frame [N]
  Eigen::Vector3d load_moment_ = Eigen::Vector3d::Zero();  ///< and its moment about the origin, world frame [N m]
  bool loaded_ = false;                                    ///< setLoad gave a non-zero load

  /// The load in the body frame now, about the origin (zero without one).
  Wrench load() const;
};

}  // namespace rov_tether
