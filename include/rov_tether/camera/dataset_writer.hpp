#pragma once
// The offline dataset generator: the scenario's vehicle cameras (`cameras:`) during a run of
// rov_tether_run, written as PNG masks and depth images with an index.

#include <Eigen/Geometry>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/scenario/camera_dataset.hpp"
#include "rov_tether/scenario/scenario_runner.hpp"

namespace rov_tether::camera
{

/**
 * The vehicle's heading along a scenario's path, as scripts/simulated_rov.py steers it: towards the
 * direction of horizontal travel of the current leg, turning at most kMaxYawRate, held while the vehicle
 * does not move horizontally; it starts facing the first horizontal leg. Integrated in steps of 10 ms
 * from t = 0, so it is the same whatever times it is asked at (in increasing order).
 */
class VehicleHeading
{
 public:
  /// [deg/s], simulated_rov.py's default.
  static constexpr double kMaxYawRate = 30.0;
  explicit VehicleHeading(const Scenario& scenario);
  /// Yaw at t [s] (t not before the last call) [rad].
  double yawAt(double t);

 private:
  /// Direction of horizontal travel at t [rad]; false while the vehicle does not move horizontally.
  bool travelHeading(double t, double* heading) const;
  const Scenario& scenario_;
  double yaw_ = 0.0;
  double time_ = 0.0;
};

/// Pose of the optical frame (z forward, x right, y down) in the world for a camera of the scenario on a
/// vehicle at `vehicle` with `yaw` (level, z up).
Eigen::Isometry3d cameraPose(const ScenarioCamera& camera, const Position& vehicle, double yaw);

/**
 * A depth image an ordinary viewer shows (a 16-bit depth in mm of a tether a few metres away uses 1/10 of
 * its range and looks black): `depth_mm` (CV_16UC1, 0 = none) into `preview` (CV_8UC3, BGR), black where
 * the depth is 0, elsewhere viridis from yellow at 0 m to dark blue-violet at `far_m` [m] and beyond
 * (index 255 down to 80, so every tether pixel stands out from black with a contrast ratio of 3 or more,
 * docs/references.md; brighter is nearer). Reuses `preview`'s storage.
 */
void depthPreview(const cv::Mat& depth_mm, double far_m, cv::Mat& preview);

/**
 * Writes, for each of the scenario's cameras, DIR/cameras/<name>/mask_NNNNNN.png (8 bit, 255 where the
 * tether is visible), depth_NNNNNN.png (16 bit, depth along the optical axis in mm, 0 where there is no
 * tether or beyond 65.535 m), depth_preview_NNNNNN.png (depthPreview of it, for a person: from 0 m to the
 * deployed length plus the camera's distance from the path point, the farthest a tether point can be then)
 * and index.csv (frame,t,coverage), frame k at the last physics step at or
 * before k / rate (t is that step's time). The seabed hides what lies below it.
 */
class DatasetWriter : public CameraDataset
{
 public:
  /// `scenario` must outlive the writer. Throws std::invalid_argument for a camera CameraModel refuses.
  DatasetWriter(const Scenario& scenario, const std::string& out_dir);
  ~DatasetWriter() override;
  double nextTime() const override;
  std::string observe(const Tether& sim) override;
  std::string startWriting() override;
  std::string finishWriting() override;
  std::string commit(bool keep, std::vector<std::string>* left) override;
  const std::vector<CameraSummary>& summary() const override { return summary_; }

 private:
  struct Camera
  {
    const ScenarioCamera* spec;
    CameraModel model;
    std::string dir;  ///< Where its frames are written: the temporary directory (cameras/.<name>.partial).
    std::FILE* index = nullptr;
    std::size_t next_frame = 0;
    std::size_t frames = 0;  ///< Frames in the run: floor(duration x rate) + 1.
  };
  std::string writeFrame(Camera& camera, CameraSummary& summary, const Tether& sim, double yaw);
  /// Moves each camera's temporary directory into place (commit); "" or the error.
  std::string moveIntoPlace(std::vector<std::string>* left);
  /// Removes the temporary directories that are still there.
  void discard();

  const Scenario& scenario_;
  std::string out_dir_;
  bool made_cameras_ = false;  ///< startWriting made out_dir/cameras (discard removes it while it is empty)
  std::vector<Camera> cameras_;
  std::vector<CameraSummary> summary_;
  VehicleHeading heading_;
  TetherRenderer renderer_;
  std::unique_ptr<SeabedOccluder> seabed_;
  std::vector<const Occluder*> occluders_;
  std::vector<Position> shape_;
  std::vector<Tube> tubes_;
  cv::Mat depth_mm_;
  cv::Mat preview_;
};

}  // namespace rov_tether::camera
