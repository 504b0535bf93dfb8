#include "rov_tether/world.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{

Status World::add(const std::string& name, std::unique_ptr<Tether> tether)
{
  if (!tether)
  {
    return Status::error("world: no tether given for '" + name + "'");
  }
  if (name.empty())
  {
    return Status::error("world: a tether needs a name");
  }
  if (find(name) != npos)
  {
    return Status::error("world: there is already a tether called '" + name + "'");
  }
  tethers_.push_back(Entry{name, std::move(tether)});
  return Status::success();
}

std::size_t World::find(const std::string& name) const
{
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    if (tethers_[i].name == name)
    {
      return i;
    }
  }
  return npos;
}

Status World::advanceTo(double t, std::size_t* steps)
{
  if (!std::isfinite(t) || std::abs(t) > Tether::kMaxTime)
  {
    return Status::error("world: advance rejected: target time must be finite and within +-1e10 s");
  }
  std::size_t taken = 0;
  for (;;)
  {
    // The tether whose next step comes first takes it (ties: the first added), as Tether::advanceTo
    // decides whether a step still fits before t.
    std::size_t next = npos;
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      const Tether& candidate = *tethers_[i].tether;
      if (candidate.stepFits(t) && (next == npos || candidate.nextStepTime() < tethers_[next].tether->nextStepTime()))
      {
        next = i;
      }
    }
    if (next == npos)
    {
      break;
    }
    tethers_[next].tether->step();
    ++taken;
  }
  for (auto& entry : tethers_)
  {
    entry.tether->advanceTo(t);  // no step left to take: records t as each tether's target time
  }
  if (steps != nullptr)
  {
    *steps = taken;
  }
  return Status::success();
}

double World::time() const
{
  double earliest = tethers_.empty() ? 0.0 : tethers_.front().tether->time();
  for (const auto& entry : tethers_)
  {
    earliest = std::min(earliest, entry.tether->time());
  }
  return earliest;
}

}  // namespace rov_tether
