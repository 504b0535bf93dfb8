#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/world_contact.hpp"

namespace rov_tether
{

/// One line of the topology report (World::topology; docs/node.md "Obstacles and topology").
struct TopologyEntry
{
  enum class Kind
  {
    WrapTurns,      ///< Signed turns around an obstacle's axis, closed by the chord [-]; NaN on the axis.
    ContactAngle,   ///< Angle the tether turns through where it touches the object [rad].
    LinkingNumber,  ///< Gauss linking number with another tether, both closed by their chords [-].
    CapstanRatio,   ///< e^(mu contact angle): how much the contact can multiply a tension [-].
    WrapAngle       ///< Signed angle swept around an obstacle's axis, spool to vehicle, no chord [rad]; NaN on it.
  };
  std::size_t tether = 0;
  bool object_is_tether = false;  ///< object indexes World::obstacle, or (true) World::tether.
  std::size_t object = 0;
  Kind kind = Kind::WrapTurns;
  double value = 0.0;
};
const char* topologyKindName(TopologyEntry::Kind kind);

/// Told around each step World::advanceTo takes, with the index of the tether that steps (the node times
/// each tether's steps with it, for its load governor). The step includes what the world does for that
/// tether alone (its mounted spool placed, its carrier loaded), not the contact grid filed again before
/// it, which is every tether's.
class StepObserver
{
 public:
  virtual ~StepObserver() = default;
  virtual void beforeStep(std::size_t tether) = 0;
  virtual void afterStep(std::size_t tether) = 0;
};

/**
 * Several tethers in one scene, stepped in lockstep: advanceTo(t) takes the step that comes first in time
 * among all tethers, then the next, so no tether runs ahead of another by more than its own step. Tethers
 * with the same time_step (the usual case) step in turn, in the order they were added, at the same time.
 * This is where what tethers share goes: the obstacles they touch, and contact between them and of each with
 * itself (WorldContact; the latter off by default, setContactBetweenTethers). A world of one tether that touches
 * neither an obstacle nor itself moves as that tether alone, though it may take more sub-steps (see
 * Tether::setWorldContact); without obstacles and with contact between tethers off, it is that tether alone.
 */
class World
{
 public:
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  /// Adds a tether under a unique, non-empty name. Refuses a missing tether, an empty or taken name.
  Status add(const std::string& name, std::unique_ptr<Tether> tether);
  std::size_t size() const { return tethers_.size(); }
  Tether& tether(std::size_t i) { return *tethers_[i].tether; }
  const Tether& tether(std::size_t i) const { return *tethers_[i].tether; }
  const std::string& name(std::size_t i) const { return tethers_[i].name; }
  /// Index of the tether called `name`, or npos.
  std::size_t find(const std::string& name) const;

  /**
   * Mounts tether i's spool on the dynamic vehicle of tether `carrier` (a TMS on its umbilical): before each of
   * tether i's steps its spool outlet is put at the carrier's body pose times `outlet_offset` (body frame [m]),
   * moving (Tether::setSpoolPosition), and after each the force its cable gave the spool (Tether::spoolForce)
   * goes to the body at that point, summed over every tether mounted on it (Tether::setVehicleLoad), from the
   * body's next step on. An explicit exchange, once a step each way: stable while the mounted cable is light
   * beside the body (a tether of a few kilograms on a TMS of a tonne; docs/model.md "A TMS"). Tethers step in
   * the order they were added, so add the carrier first, or the spool lags the body by a step; with the same
   * time_step (the usual case) the spool moves smoothly, with a longer one the carrier's, in its steps. The
   * spool is put there now (the cable re-laid at rest from it, unless it is there already). If the carrier's
   * vehicle stops being dynamic (detached, reset), the spool stays where it was last put; when a dynamic
   * vehicle starts there again (Tether::vehicleStarts), the spool jumps to it (setSpoolPosition's `jump`). Refuses an
   * index out of range, a tether mounted on itself or already mounted, a carrier without a dynamic vehicle or mounted
   * (through others) on tether i, and an offset not finite or beyond VehicleParams::kMaxOffset; nothing changes then.
   */
  Status mountSpool(std::size_t i, std::size_t carrier, const Eigen::Vector3d& outlet_offset);
  /// The tether whose vehicle carries tether i's spool, or npos for a spool fixed in the world.
  std::size_t spoolCarrier(std::size_t i) const { return tethers_[i].carrier; }

  /// Advances every tether until its time is within one of its steps of t [s], in lockstep (see above).
  /// Returns the steps taken, all tethers together, through `steps` when given. Refuses a non-finite t
  /// or one beyond Tether::kMaxTime, and changes nothing then. `observer`, when given, is told around each step.
  Status advanceTo(double t, std::size_t* steps = nullptr, StepObserver* observer = nullptr);
  /// The earliest time among the tethers [s]; 0 for an empty world.
  double time() const;

  /// Replaces the obstacles (names unique and not a tether's). Refuses a missing one or a taken name.
  Status setObstacles(std::vector<std::unique_ptr<Obstacle>> obstacles);
  std::size_t obstacleCount() const { return scene_.obstacles.size(); }
  const Obstacle& obstacle(std::size_t i) const { return *scene_.obstacles[i]; }
  /// Index of the obstacle called `name`, or npos.
  std::size_t findObstacle(const std::string& name) const;
  /// Moves obstacle i (one that moves with a frame).
  void setObstaclePose(std::size_t i, const Position& position, const Eigen::Quaterniond& orientation);
  /// Contact between tethers and of a tether with itself (obstacles always collide); off by default
  /// (docs/limitations.md). Each tether moves itself out of the others and sends them the reaction.
  void setContactBetweenTethers(bool on);
  /// What tether i touched in its last step, segment by segment.
  const ContactRecord& contacts(std::size_t i) const { return contacts_[i]->record(); }

  /// The topology now, into `out` (cleared first): for each tether, its wrap turns around every obstacle with
  /// an axis, each followed by its wrap angle (topology::windingAngle: the turn building up, unclosed); for each object
  /// it touches (obstacle or tether), the contact angle and the capstan ratio with that object's friction; for each
  /// pair of tethers (once, the lower index first), the linking number. Pairs whose bounds, chords included, do not
  /// overlap cannot be linked and read 0 without the O(n m) sum.
  void topology(std::vector<TopologyEntry>& out) const;

 private:
  /// Gives every tether its WorldContact when the scene needs contact, none otherwise.
  void wireContacts();
  /// Whether a tether's cable was rebuilt (another size) since the contacts were sized for it.
  bool cableRebuilt() const;
  /// The scene's per-tether values (radius, friction, self gap; contacts resized for rebuilt cables), and
  /// the grid of every tether's segments filed again when `file`, when those changed, or when a segment
  /// has left its skin (World::advanceTo calls it once a round of steps, and when stale).
  void refreshContact(bool file);
  /// How far a cable at rest may move from where it was filed before the grid is filed again, in widest
  /// radii.
  static constexpr double kSkin = 0.5;

  /// Puts a mounted tether's spool where its carrier's body holds it: moving, or as a jump (`jump`, or a
  /// carrier that started again since).
  void placeMountedSpool(std::size_t i, bool jump = false);
  /// Gives `carrier`'s body the pull of every spool mounted on it.
  void loadCarrier(std::size_t carrier);

  struct Entry
  {
    std::string name;
    std::unique_ptr<Tether> tether;
    std::size_t carrier = npos;                               ///< Whose body carries the spool (mountSpool).
    Eigen::Vector3d outlet_offset = Eigen::Vector3d::Zero();  ///< The outlet on that body, body frame [m].
    std::uint64_t carrier_starts = 0;  ///< The carrier's Tether::vehicleStarts when the spool was last placed.
  };
  std::vector<Entry> tethers_;
  ContactScene scene_;
  std::vector<std::unique_ptr<WorldContact>> contacts_;  ///< One per tether, in World order.
  bool contact_on_ = false;                              ///< Whether tethers have their WorldContact.
  double grid_time_ = 0.0;     ///< The time of the last round's check (the first stepping tether's).
  double grid_widest_ = 0.0;   ///< The widest radius the grid was filed for [m].
  double grid_longest_ = 0.0;  ///< The longest segment it was filed for [m].
  bool grid_stale_ = true;     ///< To be filed before the next step whatever the time.
};

}  // namespace rov_tether
