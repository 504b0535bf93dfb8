#include "rov_tether/camera/dataset_writer.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "rov_tether/camera/png_file.hpp"

namespace rov_tether::camera
{
namespace
{

constexpr double kHeadingStep = 0.01;  ///< [s]

double wrap(double angle) { return std::atan2(std::sin(angle), std::cos(angle)); }

/// The lowest viridis index a tether pixel of the preview gets: below it the colours contrast with black
/// by less than 3 (index 80: 3.3; docs/references.md).
constexpr int kPreviewDarkest = 80;

}  // namespace

void depthPreview(const cv::Mat& depth_mm, double far_m, cv::Mat& preview)
{
  // viridis from kPreviewDarkest to 255, once: the colour of each index.
  static const cv::Mat palette = []
  {
    cv::Mat ramp(1, 256, CV_8UC1), colours;
    for (int i = 0; i < 256; ++i)
    {
      ramp.at<std::uint8_t>(i) = static_cast<std::uint8_t>(i);
    }
    cv::applyColorMap(ramp, colours, cv::COLORMAP_VIRIDIS);
    return colours;
  }();
  preview.create(depth_mm.rows, depth_mm.cols, CV_8UC3);
  const double span = 255.0 - kPreviewDarkest;
  for (int r = 0; r < depth_mm.rows; ++r)
  {
    const auto* mm = depth_mm.ptr<std::uint16_t>(r);
    auto* out = preview.ptr<cv::Vec3b>(r);
    for (int c = 0; c < depth_mm.cols; ++c)
    {
      const double nearness = 1.0 - std::min(1e-3 * mm[c] / far_m, 1.0);
      out[c] = mm[c] == 0 ? cv::Vec3b(0, 0, 0)
                          : palette.at<cv::Vec3b>(static_cast<int>(std::lround(kPreviewDarkest + span * nearness)));
    }
  }
}

VehicleHeading::VehicleHeading(const Scenario& scenario) : scenario_(scenario)
{
  for (const Waypoint& w : scenario_.vehicle)
  {
    if (travelHeading(w.time, &yaw_))
    {
      break;
    }
  }
}

bool VehicleHeading::travelHeading(double t, double* heading) const
{
  const auto& path = scenario_.vehicle;
  for (std::size_t k = 0; k + 1 < path.size(); ++k)
  {
    if (path[k].time <= t && t < path[k + 1].time)
    {
      const Position d = path[k + 1].position - path[k].position;
      if (std::hypot(d.x(), d.y()) / (path[k + 1].time - path[k].time) <= 1e-6)
      {
        return false;
      }
      *heading = std::atan2(d.y(), d.x());
      return true;
    }
  }
  return false;
}

double VehicleHeading::yawAt(double t)
{
  const double limit = kMaxYawRate * M_PI / 180.0 * kHeadingStep;
  while (time_ + kHeadingStep <= t + 1e-9)
  {
    double heading = 0.0;
    if (travelHeading(time_, &heading))
    {
      yaw_ = wrap(yaw_ + std::clamp(wrap(heading - yaw_), -limit, limit));
    }
    time_ += kHeadingStep;
  }
  return yaw_;
}

Eigen::Isometry3d cameraPose(const ScenarioCamera& camera, const Position& vehicle, double yaw)
{
  constexpr double kDeg = M_PI / 180.0;
  Eigen::Isometry3d world_from_vehicle = Eigen::Isometry3d::Identity();
  world_from_vehicle.translation() = vehicle;
  world_from_vehicle.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Isometry3d vehicle_from_camera = Eigen::Isometry3d::Identity();
  vehicle_from_camera.translation() = camera.position;
  vehicle_from_camera.linear() = (Eigen::AngleAxisd(camera.orientation.z() * kDeg, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(camera.orientation.y() * kDeg, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(camera.orientation.x() * kDeg, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
  // The optical frame in the camera's body frame: optical z = body x (the view), x = -body y, y = -body z.
  Eigen::Isometry3d body_from_optical = Eigen::Isometry3d::Identity();
  body_from_optical.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return world_from_vehicle * vehicle_from_camera * body_from_optical;
}

DatasetWriter::DatasetWriter(const Scenario& scenario, const std::string& out_dir)
    : scenario_(scenario), out_dir_(out_dir), heading_(scenario)
{
  for (const ScenarioCamera& spec : scenario_.cameras)
  {
    const std::size_t frames = scenario_.cameraFrames(spec);
    cameras_.push_back(Camera{&spec, CameraModel(spec.intrinsics), "", nullptr, 0, frames});
    summary_.push_back(CameraSummary{spec.name});
  }
  if (std::isfinite(scenario_.params.seabed_z))
  {
    seabed_ = std::make_unique<SeabedOccluder>(scenario_.params.seabed_z);
    occluders_.push_back(seabed_.get());
  }
}

DatasetWriter::~DatasetWriter()
{
  finishWriting();
  discard();  // a run left by an exception: its frames are not moved into place
}

namespace
{

namespace fs = std::filesystem;

/// A camera's directory, where it is written first, and where an earlier one is moved aside while it moves in.
struct CameraDirs
{
  fs::path target, partial, aside;
};

CameraDirs cameraDirs(const std::string& out_dir, const std::string& name)
{
  const fs::path cameras = fs::path(out_dir) / "cameras";
  return {cameras / name, cameras / ("." + name + ".partial"), cameras / ("." + name + ".earlier")};
}

}  // namespace

std::string DatasetWriter::startWriting()
{
  for (const Camera& camera : cameras_)
  {
    const CameraDirs dirs = cameraDirs(out_dir_, camera.spec->name);
    std::error_code ec;
    if (fs::exists(fs::symlink_status(dirs.aside, ec)))
    {
      // As the CSV files' .<name>.earlier: maybe the only copy of an earlier dataset.
      return "cannot write '" + dirs.target.string() + "/': '" + dirs.aside.string() +
             "' is in the way: an earlier dataset moved aside, by a run that stopped before it had moved its own into "
             "place (then it may be the only copy of the earlier one: put it back) or by a run that could not remove "
             "it once its own was in place (then it is the replaced one: delete it)";
    }
    const fs::file_status status = fs::symlink_status(dirs.target, ec);
    if (fs::is_symlink(status))
    {
      // Renamed aside, the link would go and a directory here take its place: the frames not where it points.
      return "cannot write '" + dirs.target.string() +
             "/': it is a symbolic link, which the run would replace with a directory (write to where it points)";
    }
    if (fs::exists(status) && !fs::is_directory(status))
    {
      return "cannot write '" + dirs.target.string() + "/': a file that is not a directory is there";
    }
  }
  std::error_code made_ec;
  made_cameras_ = fs::create_directory(fs::path(out_dir_) / "cameras", made_ec);  // true only when this made it
  for (Camera& camera : cameras_)
  {
    const CameraDirs dirs = cameraDirs(out_dir_, camera.spec->name);
    std::error_code ec;
    fs::remove_all(dirs.partial, ec);  // a run ended by SIGKILL left it: its frames past this run's must not stay
    if (!ec)
    {
      fs::create_directories(dirs.partial, ec);
    }
    camera.dir = ec ? "" : dirs.partial.string();
    camera.index = ec ? nullptr : std::fopen((dirs.partial / "index.csv").c_str(), "w");
    if (camera.index == nullptr)
    {
      finishWriting();
      discard();
      return "cannot write in '" + dirs.partial.string() + "'" + (ec ? ": " + ec.message() : "");
    }
    std::fprintf(camera.index, "frame,t,coverage\n");
  }
  return "";
}

std::string DatasetWriter::finishWriting()
{
  std::string error;
  for (Camera& camera : cameras_)
  {
    if (camera.index != nullptr)
    {
      const bool ok = std::ferror(camera.index) == 0;
      if (std::fclose(camera.index) != 0 || !ok)
      {
        error = "error while writing camera " + camera.spec->name + "'s index.csv (in '" + camera.dir + "')";
      }
      camera.index = nullptr;
    }
  }
  return error;
}

void DatasetWriter::discard()
{
  for (Camera& camera : cameras_)
  {
    if (!camera.dir.empty())
    {
      std::error_code ec;
      fs::remove_all(camera.dir, ec);
      camera.dir.clear();
    }
  }
  if (made_cameras_)
  {
    std::error_code ec;
    fs::remove(fs::path(out_dir_) / "cameras", ec);  // only while empty: what the run made, and nothing moved in
  }
}

std::string DatasetWriter::commit(bool keep, std::vector<std::string>* left)
{
  const std::string error = finishWriting();  // closed already, unless the run did not get that far
  const std::string moved = keep && error.empty() ? moveIntoPlace(left) : "";
  discard();  // what was not moved into place
  return error.empty() ? moved : error;
}

std::string DatasetWriter::moveIntoPlace(std::vector<std::string>* left)
{
  // Each camera's directory in turn: the earlier one moved aside, this run's moved in, the earlier one removed.
  // Should a move fail, that camera's earlier directory is put back; the cameras before it are in place.
  std::string done;
  for (Camera& camera : cameras_)
  {
    if (camera.dir.empty())
    {
      continue;  // never started
    }
    const CameraDirs dirs = cameraDirs(out_dir_, camera.spec->name);
    std::error_code status_ec, ec;
    const bool earlier = fs::exists(fs::symlink_status(dirs.target, status_ec));
    if (earlier)
    {
      fs::rename(dirs.target, dirs.aside, ec);
    }
    if (!ec)
    {
      fs::rename(dirs.partial, dirs.target, ec);
    }
    std::error_code back;
    if (ec && earlier && fs::exists(fs::symlink_status(dirs.aside, status_ec)))
    {
      fs::rename(dirs.aside, dirs.target, back);
    }
    if (ec)
    {
      const std::string before = done.empty() ? "" : "; replaced before it: " + done;
      return "cannot move camera " + camera.spec->name + "'s dataset into place at '" + dirs.target.string() +
             "': " + ec.message() +
             (back ? " (its earlier dataset could not be put back, and is at '" + dirs.aside.string() +
                         "': " + back.message() + before + ")"
                   : " (its earlier dataset is as it was" + before + ")");
    }
    camera.dir.clear();  // moved
    done += (done.empty() ? "" : ", ") + camera.spec->name;
    if (earlier && (fs::remove_all(dirs.aside, ec), ec))
    {
      left->push_back(dirs.aside.lexically_relative(out_dir_).string() + "/ (" + ec.message() + ")");
    }
  }
  return "";
}

double DatasetWriter::nextTime() const
{
  double next = std::numeric_limits<double>::infinity();
  for (const Camera& camera : cameras_)
  {
    if (camera.index != nullptr && camera.next_frame < camera.frames)
    {
      next = std::min(next, static_cast<double>(camera.next_frame) / camera.spec->rate);
    }
  }
  return next;
}

std::string DatasetWriter::observe(const Tether& sim)
{
  const double yaw = heading_.yawAt(sim.time());
  sim.copyPositions(shape_);
  tubes_.assign(1, Tube{&shape_, 0.5 * sim.params().diameter});
  for (std::size_t i = 0; i < cameras_.size(); ++i)
  {
    Camera& camera = cameras_[i];
    const double due = static_cast<double>(camera.next_frame) / camera.spec->rate;
    if (camera.index != nullptr && camera.next_frame < camera.frames && due <= sim.time() + sim.params().time_step)
    {
      const std::string error = writeFrame(camera, summary_[i], sim, yaw);
      if (!error.empty())
      {
        return error;
      }
    }
  }
  return "";
}

std::string DatasetWriter::writeFrame(Camera& camera, CameraSummary& summary, const Tether& sim, double yaw)
{
  const Eigen::Isometry3d pose = cameraPose(*camera.spec, scenario_.vehicleAt(sim.time()), yaw);
  const RenderStats stats = renderer_.render(camera.model, pose, tubes_, occluders_);
  depth_mm_.create(camera.model.height(), camera.model.width(), CV_16UC1);
  depth_mm_.setTo(0);
  auto* mm = depth_mm_.ptr<std::uint16_t>();
  const auto* depth = renderer_.depth().ptr<float>();
  for (int p : renderer_.pixels())
  {
    const double value = std::round(1000.0 * depth[p]);
    mm[p] = value <= 65535.0 ? static_cast<std::uint16_t>(value) : 0;
  }
  char name[32];
  std::snprintf(name, sizeof(name), "%06zu.png", camera.next_frame);
  const std::string mask_path = camera.dir + "/mask_" + name;
  const std::string depth_path = camera.dir + "/depth_" + name;
  const std::string preview_path = camera.dir + "/depth_preview_" + name;
  // Every tether point is within the deployed length of the attachment (the path point), and the camera
  // within |position| of it: the farthest a tether point can be in this frame.
  depthPreview(depth_mm_, sim.deployedLength() + camera.spec->position.norm(), preview_);
  if (!writePng(mask_path, renderer_.mask()) || !writePng(depth_path, depth_mm_) || !writePng(preview_path, preview_))
  {
    return "cannot write '" + mask_path + "', '" + depth_path + "' or '" + preview_path + "'";
  }
  std::fprintf(camera.index, "%zu,%.6f,%.6g\n", camera.next_frame, sim.time(), stats.coverage);
  ++camera.next_frame;
  summary.mean_coverage += (stats.coverage - summary.mean_coverage) / static_cast<double>(++summary.frames);
  summary.max_coverage = std::max(summary.max_coverage, stats.coverage);
  summary.frames_with_tether += stats.pixels > 0;
  return "";
}

}  // namespace rov_tether::camera

// The module's entry point, loaded by makeCameraDataset (scenario/camera_dataset.cpp) with dlopen: C linkage,
// so its name is known without C++ mangling. A camera CameraModel refuses is an error, not an exception.
extern "C" __attribute__((visibility("default"))) rov_tether::CameraDataset* rov_tether_make_camera_dataset(
    const rov_tether::Scenario* scenario, const std::string* out_dir, std::string* error)
{
  try
  {
    return new rov_tether::camera::DatasetWriter(*scenario, *out_dir);
  }
  catch (const std::invalid_argument& e)
  {
    *error = e.what();
    return nullptr;
  }
}
