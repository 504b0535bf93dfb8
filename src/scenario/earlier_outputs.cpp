#include "rov_tether/scenario/earlier_outputs.hpp"

#include <algorithm>
#include <cstdlib>
#include <iterator>

namespace rov_tether
{

namespace
{

namespace fs = std::filesystem;

constexpr const char* kCsvFiles[] = {"state.csv", "shape.csv", "vehicle.csv", "topology.csv"};
constexpr const char* kFramePrefixes[] = {"depth_preview_", "mask_", "depth_"};

bool isCsvOutput(const fs::path& file)
{
  return std::find_if(std::begin(kCsvFiles), std::end(kCsvFiles),
                      [&](const char* name) { return file.filename() == name; }) != std::end(kCsvFiles);
}

/// The frame number of a frame file's name (mask_000012.png: 12), or -1 for any other name.
long frameNumber(const std::string& name)
{
  for (const char* prefix : kFramePrefixes)
  {
    const std::string p(prefix);
    if (name.size() == p.size() + 10 && name.compare(0, p.size(), p) == 0 &&
        name.compare(name.size() - 4, 4, ".png") == 0 &&
        std::all_of(name.begin() + static_cast<std::ptrdiff_t>(p.size()), name.end() - 4,
                    [](char c) { return c >= '0' && c <= '9'; }))
    {
      return std::strtol(name.c_str() + p.size(), nullptr, 10);
    }
  }
  return -1;
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
  // A directory this run does not write into is an earlier run's tether directory only if an earlier world run
  // wrote here (every run with a tethers list writes DIR/topology.csv; this run has not replaced it yet) and it
  // holds what a tether directory holds, no run of its own (a topology.csv or a directory: cameras/, tethers').
  // Anything else is another run's folder (`--out results` beside results/dive1/), which mixes with nothing this run
  // writes: its files were named one by one, every other run's.
  std::error_code topology_ec;
  const bool earlier_world = fs::is_regular_file(out_dir / "topology.csv", topology_ec);
  const auto earlierTetherDirectory = [&](const fs::path& dir)
  {
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
    if (!own && !(earlier_world && earlierTetherDirectory(it->path())))
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
  // The cameras' directories and frames.
  const fs::path cameras = out_dir / "cameras";
  std::vector<fs::path> dirs;
  std::error_code cameras_ec;
  for (fs::directory_iterator it(cameras, fs::directory_options::skip_permission_denied, cameras_ec), end;
       !cameras_ec && it != end; it.increment(cameras_ec))
  {
    std::error_code dir_ec;
    if (fs::is_directory(it->path(), dir_ec))
    {
      dirs.push_back(it->path());
    }
  }
  std::sort(dirs.begin(), dirs.end());
  for (const fs::path& dir : dirs)
  {
    const auto camera = std::find_if(scenario.cameras.begin(), scenario.cameras.end(),
                                     [&](const ScenarioCamera& c) { return c.name == dir.filename().string(); });
    const long frames = camera == scenario.cameras.end() ? 0 : static_cast<long>(scenario.cameraFrames(*camera));
    std::size_t past = 0, files = 0;
    std::error_code dir_ec;
    for (fs::directory_iterator it(dir, fs::directory_options::skip_permission_denied, dir_ec), end;
         !dir_ec && it != end; it.increment(dir_ec))
    {
      const std::string name = it->path().filename().string();
      ++files;
      past += frameNumber(name) >= frames ? 1 : 0;
    }
    const std::string where = "cameras/" + dir.filename().string() + "/";
    if (camera == scenario.cameras.end() && files > 0)
    {
      found.push_back(where + " (" + std::to_string(files) + (files == 1 ? " file" : " files") +
                      ": a camera this scenario does not have)");
    }
    else if (past > 0)
    {
      found.push_back(where + " (" + std::to_string(past) + " frame files past this run's " + std::to_string(frames) +
                      " frames)");
    }
  }
  return found;
}

}  // namespace rov_tether
