#pragma once

#include <deque>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/status.hpp"

namespace rov_tether
{

/**
 * Where the vehicle's attachment point is: the queue of timed samples the caller fed, linear
 * interpolation between them, and the jump rule.
 *
 * The first sample attaches the vehicle when the simulation reaches its time (attachIfDue), so when a
 * sample arrives does not change a run. A sample further from the previous one than the vehicle could
 * have moved, max_speed * dt + max_jump for samples dt apart, is a jump: the position goes there when the
 * simulation reaches it, without interpolation, and the tether re-lays its cable (advance() reports it).
 */
class VehicleTrack
{
 public:
  /// Samples that may wait ahead of the simulation; more are refused until it advances. The node runs the
  /// physics up to 2 s (stale_pose_timeout) behind its poses when some tether's poses come sparsely, so a
  /// tether fed at 1 kHz needs some 2,000 [-].
  static constexpr std::size_t kMaxSamples = 4096;

  /// Attaches the vehicle at `position` now, with that sample at time t.
  void attachAt(double t, const Position& position);
  /// Queues a sample (finite values are the caller's check). Refuses times older than the last sample
  /// (the same time replaces it, and the success's message says so) and more than kMaxSamples waiting. `now` [s] is the
  /// simulation's time: where it has passed the last sample (the vehicle held there), the move starts from there at
  /// `now` (or at t, if that is earlier). A move beyond max_speed [m/s] * dt + max_jump [m] from the sample dt before
  /// is a jump.
  Status add(double t, const Position& position, double max_jump, double max_speed, double now);
  /// The rule add() keeps for the order of samples, for any stream of them (a dynamic vehicle's setpoints too): a
  /// sample at t after the last one, at last_time [s], is taken; an older one refused; one at the same time
  /// replaces the last, `moved` [m] from it, and the success's message says so.
  static Status order(double t, double last_time, double moved);
  /// Drops the samples and detaches: the last particle becomes a free end.
  void detach();

  /// True when the vehicle is not attached yet and its first sample's time has come by t [s]: attaches it
  /// at that sample (position()), or, when that sample is more than `late` [s] before t, where the samples
  /// put it at t (the ones before were never simulated: a node that started late with poses queued); the
  /// tether then lays its cable out to it.
  bool attachIfDue(double t, double late);
  /// Where the samples put the attachment at time t [s] (attached only), and whether a jump was passed.
  struct Target
  {
    Position position;
    bool jumped;
  };
  Target advance(double t);

  bool attached() const { return attached_; }
  /// True when samples are queued (the vehicle may attach or move).
  bool active() const { return attached_ || !samples_.empty(); }
  /// The attachment point as last set [m].
  const Position& position() const { return position_; }
  void setPosition(const Position& position) { position_ = position; }

 private:
  struct Sample
  {
    double time;
    Position position;
    bool jump;
  };
  std::deque<Sample> samples_;
  Position position_ = Position::Zero();
  bool attached_ = false;
};

}  // namespace rov_tether
