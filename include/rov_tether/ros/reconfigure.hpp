#pragma once
// dynamic_reconfigure's TetherConfig to and from the core's TetherParams, through the parameter table's names.

#include <string>

#include "rov_tether/TetherConfig.h"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether::ros_layer
{

/// Applies every dynamic_reconfigure field to `params` through the core's setParameter (the .cfg uses
/// the model's parameter names). Returns "" or every problem, each naming its parameter; it does not
/// validate relations between fields (TetherParams::validate() does).
std::string configToParams(const TetherConfig& config, TetherParams* params);

/// The dynamic_reconfigure view of `params` (every field of the .cfg, read by name); `auto` values show as
/// what they resolve to.
TetherConfig paramsToConfig(const TetherParams& params);

/// A dynamic_reconfigure request applied to `requested`, the parameters as the user asked for them (`auto`
/// kept apart from what it resolves to). Only the fields of `asked` that differ from what the server shows,
/// paramsToConfig(*requested), are set: a field left as shown keeps what was asked, so `iterations: auto`
/// stays auto and is resolved again from the new values, while a new number for iterations ends auto.
/// Returns "" or every problem, each naming its parameter (the field's own, then validate()'s, then a change
/// `auto` would override at once: substeps under lumped_mass with `iterations: auto`); `requested` is
/// changed only when there is none.
std::string applyConfigChanges(const TetherConfig& asked, TetherParams* requested);

/// Every numeric field of the .cfg at the table's lower (`upper` false) or upper bound, for the server's
/// setConfigMin/Max: rqt_reconfigure shows these ranges, while the .cfg itself gives none, so the server
/// never clamps a request before the node has checked it.
TetherConfig configBounds(bool upper);

/// The fields in which `asked` differs from `used`, as "name: asked A, used U" joined by "; " ("" if none):
/// the WARN of a refused dynamic_reconfigure change names what was asked and what runs.
std::string configDifferences(const TetherConfig& asked, const TetherConfig& used);

}  // namespace rov_tether::ros_layer
