#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "rov_tether/status.hpp"
#include "rov_tether/tether.hpp"

namespace rov_tether
{

/**
 * Several tethers in one scene, stepped in lockstep: advanceTo(t) takes the step that comes first in time
 * among all tethers, then the next, so no tether runs ahead of another by more than its own step. Tethers
 * with the same time_step (the usual case) step in turn, in the order they were added, at the same time.
 * This is where what tethers share goes: the colliders they touch and contact between them (a later step
 * of the design, see docs/architecture.md). A world of one tether behaves exactly as that tether alone.
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

  /// Advances every tether until its time is within one of its steps of t [s], in lockstep (see above).
  /// Returns the steps taken, all tethers together, through `steps` when given. Refuses a non-finite t
  /// or one beyond Tether::kMaxTime, and changes nothing then.
  Status advanceTo(double t, std::size_t* steps = nullptr);
  /// The earliest time among the tethers [s]; 0 for an empty world.
  double time() const;

 private:
  struct Entry
  {
    std::string name;
    std::unique_ptr<Tether> tether;
  };
  std::vector<Entry> tethers_;
};

}  // namespace rov_tether
