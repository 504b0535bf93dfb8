#pragma once
/**
 * Contact of one tether with what its World holds: the obstacles, the other tethers and itself. The cable is
 * a chain of capsules of its diameter; a capsule that overlaps something is moved out along the way out
 * (its two particles in proportion to their inverse masses and to where along it the contact sits). Then
 * each particle of a touching capsule may be held back, over the whole step, by no more than mu times its
 * normal displacement: the larger of the corrections that pushed it out (a load such as its weight
 * pressing it in) and the pull of its two segments into the contact, lambda w, from the solve's
 * multipliers (a tensioned cable around a pillar). The hold is a force the solve balances: the step is
 * solved again from its prediction moved back by the holds (ConstraintSolver::solve), starting from the
 * last step's holds, so the tension carries friction. Position-based Coulomb friction (Macklin et al. 2014)
 * with the normal force a wrapped cable really exerts, so the capstan law holds (docs/references.md).
 * The other tethers are fixed while this one steps (World steps them in turn): each tether moves itself out
 * of the others, so none passes through another, and each push sends the other tether the opposite momentum,
 * which it takes at its next sub-step (ContactScene::reaction): the one lying on another weighs on it, the
 * one dragged across another drags it along. Their capsules and this one's own
 * non-adjacent capsules are found through a uniform grid (SegmentGrid) that World files again when a segment
 * leaves its skin, and the pairs of segments it lists when filed.
 *
 * What was touched in the last step is kept per segment (record()), for the topology report (contact angle,
 * capstan ratio) and the contact markers. Nothing here allocates after construction.
 */

#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "rov_tether/core/contact.hpp"
#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/segment_grid.hpp"

namespace rov_tether
{

/// What each segment of one tether touched in its last step: -1 for nothing.
struct ContactRecord
{
  std::vector<int> obstacle;    ///< Index of the obstacle touched (World::obstacle), per segment.
  std::vector<int> tether;      ///< Index of the tether touched (itself included), per segment.
  std::vector<Position> point;  ///< Where (the deepest point on the segment's axis), per segment [m].

  void clear()
  {
    std::fill(obstacle.begin(), obstacle.end(), -1);
    std::fill(tether.begin(), tether.end(), -1);
  }
};

/// The shared scene a WorldContact reads: obstacles with their bounds, every tether's cable, radius and
/// friction, and the grid of their segments. Owned by World.
struct ContactScene
{
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  std::vector<Aabb> bounds;            ///< obstacles[i]->bounds(), refreshed when poses change.
  std::vector<const Cable*> cables;    ///< Every tether's cable, in World order.
  std::vector<double> radius;          ///< Every tether's capsule radius [m].
  std::vector<double> cable_friction;  ///< Every tether's Coulomb coefficient against a cable [-].
  std::vector<std::size_t> self_gap;   ///< Segments this close along one cable never collide.
  SegmentGrid grid;                    ///< Every tether's segments and their pairs (World::refreshContact).
  bool between_tethers = false;        ///< Contact between tethers and of a tether with itself.
  /// Per tether, per particle: the change of velocity the other tethers' contacts gave it since its last
  /// sub-step (the reaction of each push, Newton's third law), which it takes at its next one [m/s]. The
  /// one part of the scene the contacts write: each adds to the others' and takes its own.
  std::vector<std::vector<Position>> reaction;
};

class WorldContact : public Contact
{
 public:
  /// Contact of tether `self` with the scene, which it reads, and whose `reaction` it writes.
  WorldContact(ContactScene& scene, std::size_t self) : scene_(scene), reaction_(scene.reaction), self_(self) {}
  void project(Cable& cable, std::size_t begin, std::size_t end, const std::vector<double>& stretch,
               bool first_pass) override;
  bool holds() const override { return true; }
  bool updateHold(const Cable& cable, const std::vector<double>& stretch, bool first) override;
  void applyHold(Cable& cable) const override;
  void warmStart(Cable& cable, double h) override;
  void takeReaction(Cable& cable, std::size_t begin, std::size_t end, double h) override;
  void sendReaction() override;
  void forget() override;
  void friction(Cable& cable, const std::vector<double>& stretch) override;
  void limitRebound(Cable& cable, double h) const override;
  /// The fastest a contact sends a particle off its surface [m/s]: faster than the vehicles and moving
  /// obstacles of an ROV scene (a ship's hull at 10 knots moves 5.1 m/s), slower than what undoing an old
  /// overlap in one sub-step would give (a 0.1 m overlap in 5 ms: 20 m/s).
  static constexpr double kMaxRebound = 8.0;
  /// Sizes the record and the candidate list for the scene as it now is (not in the hot loop).
  void resize();
  const ContactRecord& record() const { return record_; }
  double lastPullIn() const override { return state_.deepest; }

 private:
  /// Per particle: the other tether's segment it last slid on in this step and where along it; tether -1
  /// when it touched none, kNotATether when it also touched an obstacle or its own cable.
  struct Partner
  {
    int tether = -1;
    std::size_t segment = 0;
    double u = 0.0;
  };
  static constexpr int kNotATether = -2;

  /// What this contact keeps from one call to the next, within a step (its passes) and into the next step
  /// (the holds that warm-start it): per particle unless said. Changed only by the non-const methods.
  struct StepState
  {
    /// This step: the contact normal (summed), the normal corrections [m] (-1: untouched), the friction
    /// coefficient and the displacement friction already took back [m].
    std::vector<Position> normal;
    std::vector<double> pushed, mu, held;
    std::vector<double> hold;    ///< How far friction holds the particle back in the solve [m].
    std::vector<Position> slip;  ///< The direction it holds against (the first solve's slip).
    std::vector<Partner> partner;
    std::vector<std::size_t> touched;  ///< The particles touched this step, in order.
    /// The particles touched in the last step, whose holds (hold, slip, for a step of warm_h [s])
    /// warm-start this one.
    std::vector<std::size_t> warm;
    double warm_h = 0.0;
    double h = 1.0;        ///< This sub-step's length [s] (takeReaction).
    double deepest = 0.0;  ///< lastPullIn() [m].
    /// Per segment: what a mesh keeps between its queries (Obstacle::pushNear).
    std::vector<Obstacle::Near> near_obstacle;
    std::vector<std::size_t> touching;  ///< Segments that touched something in the step's first sweep.
  };
  /// The reactions this pass of the contacts owes the other tethers, per tether and particle [m/s], with the
  /// (tether, particle) pairs noted (each once: mark); sendReaction() hands over the last pass's.
  struct Owed
  {
    std::vector<std::vector<Position>> sent;
    std::vector<std::vector<std::uint8_t>> mark;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> list;
  };
  /// Scratch of one projection, meaningless between calls.
  struct Scratch
  {
    std::vector<int> candidates;           ///< Obstacles that overlap this cable's bounds this step.
    std::vector<SegmentGrid::Entry> near;  ///< Grid query result.
    std::vector<std::size_t> deep;         ///< Segments the next sweep revisits (deep in the last one).
    std::vector<std::size_t> next_deep;
  };

  /// Moves segment j's particles so the point at t clears by depth along n, and notes for each the normal,
  /// the correction and the friction coefficient; returns the momentum given along n, m dx [kg m].
  double resolve(Cable& cable, std::size_t j, const Push& push, double mu);
  /// Forgets the reactions noted in this pass.
  void clearSent();
  /// Notes the reaction to a push of this tether of `momentum` along n off tether k's segment s at u.
  void react(std::size_t k, std::size_t s, const Push& push, double momentum);
  /// Resolves segment j against the obstacles and (when `others`) the cables; returns its deepest overlap.
  double contactSegment(Cable& cable, std::size_t j, double r, double widest, bool others, std::size_t gap);
  /// Resolves segment j against the candidate obstacles; returns its deepest overlap. `push`: the last
  /// push found (contactCables starts from it).
  double contactObstacles(Cable& cable, std::size_t j, double r, Push* push);
  /// Resolves segment j against the segments of the cables near it (its own beyond `gap`); returns its
  /// deepest overlap.
  double contactCables(Cable& cable, std::size_t j, double r, double widest, std::size_t gap, Push* push);
  /// The start of a pass: the first of a step begins the record and the holds' bookkeeping anew; a later
  /// one keeps the particles touched so far.
  void beginPass(bool first_pass);
  /// The obstacles whose bounds overlap those of the particles [lo, hi] (scratch_.candidates).
  void findCandidates(const Cable& cable, std::size_t lo, std::size_t hi, double r);
  /// Gauss-Seidel sweeps over the segments [lo, hi).
  void sweepSegments(Cable& cable, std::size_t lo, std::size_t hi, bool first_pass);
  static constexpr int kContactSweeps = 6;
  /// Sweeps stop when no overlap exceeded this x the radius: a quarter of the 10% of the diameter the
  /// issue allows a contact to overlap.
  static constexpr double kSettled = 0.05;
  /// The most friction can hold particle i back this step: mu times the larger of its normal corrections
  /// and its segments' pull into the contact, lambda w [m]; the unit normal (zero when untouched); and mu
  /// times that pull alone [m] (`pulled`).
  double holdLimit(const Cable& cable, std::size_t i, const std::vector<double>& stretch, Position* normal,
                   double* pulled) const;
  /// The pull of particle i's two segments into a contact of normal n, lambda [kg m] (0 when it pulls out).
  static double pullInto(const Cable& cable, std::size_t i, const std::vector<double>& stretch, const Position& n);

  const ContactScene& scene_;
  std::vector<std::vector<Position>>& reaction_;  ///< scene_.reaction, which this contact writes.
  std::size_t self_;
  ContactRecord record_;
  StepState state_;
  Owed owed_;
  Scratch scratch_;
};

}  // namespace rov_tether
