#include "rov_tether/scenario/earlier_outputs.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <utility>

#include "rov_tether/core/world.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"

namespace rov_tether
{

namespace
{

namespace fs = std::filesystem;

constexpr const char* kCsvFiles[] = {"state.csv", "shape.csv", "vehicle.csv", "topology.csv"};

bool isCsvOutput(const fs::path& file)
{
  return std::find_if(std::begin(kCsvFiles), std::end(kCsvFiles),
                      [&](const char* name) { return file.filename() == name; }) != std::end(kCsvFiles);
}

/// The tethers the runner's topology.csv at `file` names: every row's `tether`, and the `object` of a
/// linking_number row, the one kind whose object is always a tether (a wrap's is an obstacle, a contact's either, so
/// an obstacle named like a folder is never taken for a tether). Every pair of a world's tethers has its
/// linking_number row at every output time, so a world of two or more names all its tethers; one of a single tether
/// names it only in its wraps and contacts. Empty for a file with another header (no topology.csv of the runner's)
/// or with no row.
std::vector<std::string> topologyTethers(const fs::path& file)
{
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
  {
    return names;  // none, or no file the runner wrote (a FIFO would block the read)
  }
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != kTopologyCsvHeader)
  {
    return names;
  }
  const std::string linking = topologyKindName(TopologyEntry::Kind::LinkingNumber);
  const auto add = [&](std::string name)
  {
    if (std::find(names.begin(), names.end(), name) == names.end())
    {
      names.push_back(std::move(name));
    }
  };
  while (std::getline(in, line))
  {
    // t,tether,object,kind,value: a tether's name has no comma (isTetherName), nor an obstacle's (validate in
    // obstacle.cpp; a file of an older build may hold one), so the object is taken as what lies between the tether
    // and the last two fields. A line of fewer fields gives nothing.
    const std::size_t t_end = line.find(',');
    const std::size_t tether_end = t_end == std::string::npos ? t_end : line.find(',', t_end + 1);
    const std::size_t value_start = line.rfind(',');
    const std::size_t kind_start = tether_end == std::string::npos ? tether_end : line.rfind(',', value_start - 1);
    if (kind_start == std::string::npos || kind_start <= tether_end)
    {
      continue;
    }
    add(line.substr(t_end + 1, tether_end - t_end - 1));
    if (line.compare(kind_start + 1, value_start - kind_start - 1, linking) == 0)
    {
      add(line.substr(tether_end + 1, kind_start - tether_end - 1));
    }
  }
  return names;
}

}  // namespace

std::vector<std::string> earlierOutputs(const Scenario& scenario, const fs::path& out_dir,
                                        const std::vector<fs::path>& written)
{
  std::vector<std::string> found;
  std::error_code ec;
  if (!fs::is_directory(out_dir, ec))
  {
    return found;
  }
  const auto writes = [&](const fs::path& file)
  { return std::find(written.begin(), written.end(), file) != written.end(); };
  // The directories one level down this run writes into (a tethers list's DIR/<name>/).
  std::vector<fs::path> own_dirs;
  for (const fs::path& file : written)
  {
    const fs::path relative = file.lexically_relative(out_dir);
    if (std::distance(relative.begin(), relative.end()) == 2)
    {
      own_dirs.push_back(*relative.begin());
    }
  }
  // A directory this run does not write into is an earlier run's tether directory only if the earlier run's
  // topology.csv in out_dir (every world run writes one; this run has not replaced it yet) names it as one of its
  // tethers, and it holds what a tether directory holds, no run of its own (a topology.csv or a directory: cameras/,
  // tethers'). That a topology.csv is there is no proof: a single tether with obstacles writes one too, beside its
  // own state.csv, and a world run into its own folder again reads the one it wrote before; either took every folder
  // of CSVs beside it for an earlier world's. A single tether is called `tether` in its topology.csv, and writes its
  // state.csv in out_dir itself: with a state.csv in out_dir, `tether` is taken for that single tether, not for a
  // directory. A topology.csv with no row (a tethers list of one that wrapped and touched nothing) names no tether,
  // and then no directory is taken: a folder is named only on that evidence, never on a guess. Anything else is
  // another run's folder (`--out results` beside results/dive1/), which mixes with nothing this run writes: its
  // files were named one by one, every other run's.
  std::vector<std::string> earlier_tethers = topologyTethers(out_dir / "topology.csv");
  std::error_code state_ec;
  if (fs::is_regular_file(out_dir / "state.csv", state_ec))
  {
    earlier_tethers.erase(std::remove(earlier_tethers.begin(), earlier_tethers.end(), "tether"), earlier_tethers.end());
  }
  const auto earlierTetherDirectory = [&](const fs::path& dir)
  {
    if (std::find(earlier_tethers.begin(), earlier_tethers.end(), dir.filename().string()) == earlier_tethers.end())
    {
      return false;
    }
    std::error_code dir_ec;
    for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, dir_ec), end;
         !dir_ec && it != end; it.increment(dir_ec))
    {
      std::error_code entry_ec;
      if (it->path().filename() == "topology.csv" || fs::is_directory(it->path(), entry_ec))
      {
        return false;
      }
    }
    return !dir_ec;
  };
  // The CSV files, in out_dir and one level down (a tethers list's directories), in name order. An entry that
  // cannot be read is passed over, not the rest with it.
  std::vector<fs::path> csv;
  const auto take = [&](const fs::path& file)
  {
    std::error_code file_ec;
    if (fs::is_regular_file(file, file_ec) && isCsvOutput(file) && !writes(file))
    {
      csv.push_back(file);
    }
  };
  for (fs::directory_iterator it(out_dir, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
       it.increment(ec))
  {
    take(it->path());
    std::error_code dir_ec;
    if (!fs::is_directory(it->path(), dir_ec) || it->path().filename() == "cameras")
    {
      continue;
    }
    const bool own = std::find(own_dirs.begin(), own_dirs.end(), it->path().filename()) != own_dirs.end();
    if (!own && !earlierTetherDirectory(it->path()))
    {
      continue;  // another run's folder
    }
    for (fs::directory_iterator sub(it->path(), fs::directory_options::skip_permission_denied, dir_ec), last;
         !dir_ec && sub != last; sub.increment(dir_ec))
    {
      take(sub->path());
    }
  }
  std::sort(csv.begin(), csv.end());
  for (const fs::path& file : csv)
  {
    found.push_back(file.lexically_relative(out_dir).string());
  }
  // The directories of cameras this scenario does not have (each of its own cameras' directories is replaced whole
  // when the run succeeds: DatasetWriter). Names starting with '.' are the runs' temporaries, not outputs.
  const fs::path cameras = out_dir / "cameras";
  std::vector<fs::path> dirs;
  std::error_code cameras_ec;
  for (fs::directory_iterator it(cameras, fs::directory_options::skip_permission_denied, cameras_ec), end;
       !cameras_ec && it != end; it.increment(cameras_ec))
  {
    std::error_code dir_ec;
    const std::string name = it->path().filename().string();
    const bool ours = std::any_of(scenario.cameras.begin(), scenario.cameras.end(),
                                  [&](const ScenarioCamera& c) { return c.name == name; });
    if (!ours && name.front() != '.' && fs::is_directory(it->path(), dir_ec))
    {
      dirs.push_back(it->path());
    }
  }
  std::sort(dirs.begin(), dirs.end());
  for (const fs::path& dir : dirs)
  {
    std::size_t files = 0;
    std::error_code dir_ec;
    for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, dir_ec), end;
         !dir_ec && it != end; it.increment(dir_ec))
    {
      ++files;
    }
    if (files > 0)
    {
      found.push_back("cameras/" + dir.filename().string() + "/ (" + std::to_string(files) +
                      (files == 1 ? " file" : " files") + ": a camera this scenario does not have)");
    }
  }
  return found;
}

}  // namespace rov_tether
