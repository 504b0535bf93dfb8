#include "rov_tether/core/vehicle_track.hpp"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace rov_tether
{

void VehicleTrack::attachAt(double t, const Position& position)
{
  attached_ = true;
  position_ = position;
  samples_.assign(1, Sample{t, position, false});
}

Status VehicleTrack::add(double t, const Position& position, double max_jump, double max_speed, double now)
{
  if (!attached_ && samples_.empty())
  {
    samples_.push_back(Sample{t, position, false});
    return Status::success();
  }
  Status done = samples_.empty() ? Status::success()
                                 : order(t, samples_.back().time, (position - samples_.back().position).norm());
  if (!done.ok)
  {
    return done;
  }
  // Held: the simulation went on past the last sample with no newer one (poses that stopped). Decided before a
  // duplicate below takes its sample out: with two queued and the simulation between them, the one left is not held.
  const bool held = attached_ && samples_.size() == 1 && now > samples_.back().time;
  if (!samples_.empty() && t == samples_.back().time)
  {
    samples_.pop_back();  // a duplicate stamp replaces the sample it repeats (the later message is the better fix)
  }
  if (samples_.size() >= kMaxSamples)
  {
    // Consumed samples are dropped as the simulation passes them, so a full buffer holds samples the
    // simulation has not reached: dropping any of them would make the vehicle jump.
    std::ostringstream out;
    out << "vehicle sample rejected: " << samples_.size() << " samples already wait ahead of the simulation (at " << now
        << " s); advance it first";
    return Status::error(out.str());
  }
  if (held && !samples_.empty())
  {
    // The simulation went on past the last sample with the vehicle held there (poses that stopped): it is there
    // until now, not only at the sample's time. Moving from the sample's time, the end would cover at once the
    // share of the way the gap's time had already used, a leap of most of it (kN on a brake's tether); from now,
    // it takes the time left to the new sample, and is a jump if it cannot in that time.
    samples_.back().time = std::min(now, t);
  }
  // The sample before (none left when this one replaced the only one: then it is where the vehicle is).
  const Position& previous = samples_.empty() ? position_ : samples_.back().position;
  const double dt = samples_.empty() ? 0.0 : t - samples_.back().time;
  const bool jump = (position - previous).norm() > max_speed * dt + max_jump;
  samples_.push_back(Sample{t, position, jump});
  return done;
}

Status VehicleTrack::order(double t, double last_time, double moved)
{
  if (t > last_time)
  {
    return Status::success();
  }
  std::ostringstream out;
  out << std::fixed << std::setprecision(6);
  if (t < last_time)
  {
    out << "vehicle sample rejected: time " << t << " s is older than the last sample at " << last_time << " s";
    return Status::error(out.str());
  }
  out << "a sample stamped " << t << " s again replaced the one before (" << std::setprecision(3) << moved
      << " m from it)";
  return {true, out.str()};
}

void VehicleTrack::detach()
{
  attached_ = false;
  samples_.clear();
}

bool VehicleTrack::attachIfDue(double t, double late)
{
  if (attached_ || samples_.empty() || samples_.front().time > t)
  {
    return false;
  }
  attached_ = true;
  position_ = samples_.front().position;
  if (t - samples_.front().time > late)
  {
    // The samples before t were never simulated (they queued while a node started): attach where they put
    // the vehicle at t. A jump among them is moot, for the cable is laid out fresh.
    position_ = advance(t).position;
  }
  return true;
}

VehicleTrack::Target VehicleTrack::advance(double t)
{
  bool jumped = false;
  while (samples_.size() >= 2 && samples_[1].time <= t)
  {
    samples_.pop_front();
    jumped = jumped || samples_.front().jump;
    samples_.front().jump = false;
  }
  if (samples_.empty())
  {
    return {position_, false};
  }
  Position target = samples_.front().position;
  if (samples_.size() >= 2 && t > samples_[0].time && !samples_[1].jump)
  {
    const double alpha = (t - samples_[0].time) / (samples_[1].time - samples_[0].time);
    target = samples_[0].position + alpha * (samples_[1].position - samples_[0].position);
  }
  return {target, jumped};
}

}  // namespace rov_tether
