#pragma once
// ~set_winch's rules (rov_tether/SetWinch): what a request changes in the winch, and the answer to one taken.
// The node (tether_node.cpp) applies them; without a master, so that they are unit-tested.
#include <string>

#include "rov_tether/SetWinch.h"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether::ros_layer
{

/// The winch parameters and target length [m] a SetWinch request asks for, on top of `params` and `*target` (the
/// target length in force, NaN for none): "" when the request is valid, else why not, and nothing is changed then.
/// A malformed field (an unknown mode, a negative or NaN tension, a non-finite speed or target) is refused alone;
/// otherwise every problem of the request is listed. A field left at 0 keeps what is in force (`mode` "" the mode),
/// except that a request naming `mode: speed` sets `speed` and `target_length` as sent (speed 0 stands, target_length 0
/// clears the target): a request of one field changes that field only. `speed` and `target_length` act in speed mode
/// only, so a request that leaves the winch in another mode with either set is refused, as is a target length without a
/// speed to go there at; leaving speed mode clears the target. A request refused for a parameter the service does
/// not set (a constant_tension target above what max_winch_pull, set by dynamic_reconfigure, lets the motor pull)
/// says so: the parameter, its value, and how to change it on the node's dynamic_reconfigure server
/// `reconfigure` (its namespace).
std::string winchRequest(const SetWinch::Request& request, TetherParams* params, double* target,
                         const std::string& reconfigure);

/// The answer to an accepted SetWinch request: the mode in force, its force, and any parameter warning.
std::string winchAnswer(const TetherParams& params, const std::string& requested_mode);

}  // namespace rov_tether::ros_layer
