#pragma once
/**
 * The runner's view of the camera dataset writer (rov_tether_camera's camera::DatasetWriter), which the
 * runner loads as a module (geometry/module.hpp) only for a scenario with `cameras:`: OpenCV and the
 * renderer are not loaded at the start of every run.
 */

#include <memory>
#include <string>
#include <vector>

#include "rov_tether/scenario/scenario_runner.hpp"

namespace rov_tether
{

/// Writes each of the scenario's cameras' frames as the run goes (it is the run's observer), into a temporary
/// directory per camera that replaces the earlier one only when the run succeeded.
class CameraDataset : public RunObserver
{
 public:
  /// Per camera: frames written, and the coverage over them.
  struct CameraSummary
  {
    std::string name;
    std::size_t frames = 0;
    std::size_t frames_with_tether = 0;
    double mean_coverage = 0.0;
    double max_coverage = 0.0;
  };
  // As a RunObserver that writes outputs of its own, which runScenario calls: startWriting creates each camera's
  // directory under a temporary name (cameras/.<name>.partial/) and its index file, refusing a
  // cameras/.<name>.earlier in the way and anything but a directory at cameras/<name>; finishWriting closes the
  // index files; commit(keep) moves each camera's directory into place (cameras/<name>/, an earlier one replaced
  // whole) when the CSV files were, and otherwise removes them.
  virtual const std::vector<CameraSummary>& summary() const = 0;
};

/// The dataset writer for `scenario`'s cameras (the scenario must outlive it) into out_dir, from the
/// rov_tether_camera module; null with the reason in `error` (a camera it refuses, or the module missing).
std::unique_ptr<CameraDataset> makeCameraDataset(const Scenario& scenario, const std::string& out_dir,
                                                 std::string* error);

}  // namespace rov_tether
