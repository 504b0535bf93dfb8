#pragma once
// What an output directory holds of an earlier run that a new run will not replace (the runner writes into a
// directory that may not be empty, and replaces only the files it writes).

#include <filesystem>
#include <string>
#include <vector>

#include "rov_tether/scenario/scenario.hpp"

namespace rov_tether
{

/// The runner's outputs in `out_dir` that a run of `scenario` writing the files `written` (and its cameras'
/// directories, each replaced whole) leaves as they are, one description each: a CSV file the runner writes
/// (state.csv, shape.csv, vehicle.csv, topology.csv, in out_dir or a tether's directory one level down) that this run
/// does not, and a camera's directory cameras/<name>/ for a camera this scenario does not have. A directory one level
/// down counts as a tether's when this run writes into it, or when out_dir's earlier topology.csv names it as a tether
/// (a row's `tether`, a linking_number row's `object`; `tether`, a single tether's name, not while out_dir holds a
/// state.csv) and the directory holds no run of its own (no topology.csv, no directory); any other is another run's
/// folder and is not looked into. Empty for a directory that does not exist.
std::vector<std::string> earlierOutputs(const Scenario& scenario, const std::filesystem::path& out_dir,
                                        const std::vector<std::filesystem::path>& written);

}  // namespace rov_tether
