#include "rov_tether/core/run_out_watch.hpp"

#include "rov_tether/core/tether.hpp"

namespace rov_tether
{

bool RunOutWatch::update(const Tether& tether)
{
  const bool full = tether.deployedLength() >= tether.params().cable_length - 1e-9;
  const bool laid = tether.layCount() != lays_;
  lays_ = tether.layCount();
  const bool ran_out = full && !was_full_ && had_spooled_ && !laid;
  was_full_ = full;
  had_spooled_ = (had_spooled_ && !laid) || !full;
  return ran_out;
}

}  // namespace rov_tether
