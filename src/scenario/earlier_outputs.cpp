#include "rov_tether/scenario/earlier_outputs.hpp"

#include <algorithm>
#include <cstdlib>

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
  // The CSV files, in out_dir and one level down (a tethers list's directories), in name order.
  std::vector<fs::path> csv;
  for (fs::recursive_directory_iterator it(out_dir, ec), end; !ec && it != end; it.increment(ec))
  {
    if (it.depth() >= 1)
    {
      it.disable_recursion_pending();
    }
    if (it->is_regular_file(ec) && isCsvOutput(it->path()) && !writes(it->path()))
    {
      csv.push_back(it->path());
    }
  }
  std::sort(csv.begin(), csv.end());
  for (const fs::path& file : csv)
  {
    found.push_back(fs::relative(file, out_dir, ec).string());
  }
  // The cameras' directories and frames.
  const fs::path cameras = out_dir / "cameras";
  std::vector<fs::path> dirs;
  for (fs::directory_iterator it(cameras, ec), end; !ec && it != end; it.increment(ec))
  {
    if (it->is_directory(ec))
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
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
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
