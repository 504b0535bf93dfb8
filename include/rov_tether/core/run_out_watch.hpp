#pragma once

#include <cstdint>

namespace rov_tether
{

class Tether;

/**
 * Whether a tether's cable runs out: the winch pays out the last of cable_length where some was still on the
 * spool. A cable laid out anew (a reset, a vehicle jump, a first pose out of reach, a recovery from a failed
 * step, a rebuild, a spool that jumped: Tether::layCount()) counts from as it is laid: laid out to all of its
 * length, it has not run out. The node's /rosout warning and the runner's summary both read it.
 */
class RunOutWatch
{
 public:
  /// After a step (or a tick of several): true exactly when the cable has run out since the last call.
  bool update(const Tether& tether);

 private:
  bool was_full_ = false;     ///< All of cable_length was out at the last call.
  bool had_spooled_ = false;  ///< Some was on the spool since the cable was laid.
  std::uint64_t lays_ = 0;    ///< Tether::layCount() at the last call.
};

}  // namespace rov_tether
