#pragma once
// The parameter table's fields by name, as TetherParams' members: what the loader by name (parameter_access.cpp)
// sets and reads, and what TetherParams::validate reads a field's values through. Private to the core.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "rov_tether/core/tether_params.hpp"

namespace rov_tether::members
{

using Vector3 = std::array<double, 3>;
using Member = std::variant<double TetherParams::*, int TetherParams::*, bool TetherParams::*,
                            std::int64_t TetherParams::*, SolverType TetherParams::*, WinchMode TetherParams::*,
                            DragModel TetherParams::*, Vector3 TetherParams::*>;

/// The one table of parameter names and their members; order is documentation order.
const std::vector<std::pair<std::string, Member>>& parameterTable();
/// The member of the parameter `name`, nullptr for none.
const Member* findMember(const std::string& name);

}  // namespace rov_tether::members
