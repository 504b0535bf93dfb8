// Speed of the camera renderer (Google Benchmark): the mask and depth image of a tether. See docs/benchmarks.md
// ("The camera renderer"). The goal: 640 x 480, 100 segments, in at most 1 ms.
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "rov_tether/camera/tether_renderer.hpp"

namespace
{

using rov_tether::Position;
using namespace rov_tether::camera;

CameraIntrinsics intrinsics(int width, int height, bool distorted)
{
  CameraIntrinsics c;
  c.width = width;
  c.height = height;
  const double f = 0.78 * width;  // a 65 degree horizontal view
  c.K = {f, 0.0, (width - 1) / 2.0, 0.0, f, (height - 1) / 2.0, 0.0, 0.0, 1.0};
  if (distorted)
  {
    c.D = {-0.28, 0.09, 0.0012, -0.0008, -0.012};
  }
  return c;
}

/// 10 m of 2 cm tether in 100 segments arching through the view from 1.5 m to 3.5 m away (partly
/// outside it at both ends), as a vehicle's camera sees its own cable; `scale` moves it closer (< 1).
std::vector<Position> arch(double scale = 1.0)
{
  std::vector<Position> points;
  for (int i = 0; i <= 100; ++i)
  {
    const double s = i / 10.0;
    points.emplace_back(scale * (-3.0 + 0.6 * s), scale * (0.3 + 0.02 * (s - 5.0) * (s - 5.0)),
                        scale * (1.5 + 2.0 * std::sin(M_PI * s / 10.0)));
  }
  return points;
}

void render(benchmark::State& state, int width, int height, bool distorted, double scale, bool seabed)
{
  const CameraModel camera(intrinsics(width, height, distorted));
  // The camera looks along the world's x axis (z up): optical z = x, optical x = -y, optical y = -z.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  std::vector<Position> points = arch(scale);
  for (auto& p : points)
  {
    p = pose * p;
  }
  const std::vector<Tube> tubes = {Tube{&points, 0.01}};
  const SeabedOccluder bed(-0.45);  // hides both ends of the arch (0.3 to 0.8 m below the camera)
  std::vector<const Occluder*> occluders;
  if (seabed)
  {
    occluders.push_back(&bed);
  }
  TetherRenderer renderer;
  RenderStats stats;
  for (auto _ : state)
  {
    stats = renderer.render(camera, pose, tubes, occluders);
    benchmark::DoNotOptimize(renderer.mask().data);
  }
  state.counters["tether_pixels"] = static_cast<double>(stats.pixels);
  state.counters["segments_drawn"] = static_cast<double>(stats.segments_drawn);
}

/// The camera of scripts/camera_cpu.sh (config/camera_720p.yaml: 1280 x 720, f = 900 px, a mild barrel)
/// looking back along its vehicle's tether, which runs past 3.5 cm beside the lens and away over 8 m (as
/// in that script, where the tether leaves the vehicle 0.3 m in front of the camera's mount): its
/// nearest segments fill a good part of the image and hide one another.
void BM_RenderMaskAndDepth720pBesideLens(benchmark::State& state)
{
  CameraIntrinsics c;
  c.width = 1280;
  c.height = 720;
  c.K = {900.0, 0.0, 639.5, 0.0, 900.0, 359.5, 0.0, 0.0, 1.0};
  c.D = {-0.05, 0.01, 0.0, 0.0, 0.0};
  const CameraModel camera(c);
  std::vector<Position> points;
  for (int i = 0; i <= 100; ++i)
  {
    const double s = i / 100.0;
    points.emplace_back(0.035 + 3.0 * s * s, 0.012 - 0.5 * s + 1.5 * s * s, -0.3 + 8.0 * s);
  }
  const std::vector<Tube> tubes = {Tube{&points, 0.01}};
  TetherRenderer renderer;
  RenderStats stats;
  for (auto _ : state)
  {
    stats = renderer.render(camera, Eigen::Isometry3d::Identity(), tubes, {});
    benchmark::DoNotOptimize(renderer.mask().data);
  }
  state.counters["tether_pixels"] = static_cast<double>(stats.pixels);
  state.counters["segments_drawn"] = static_cast<double>(stats.segments_drawn);
}

void BM_RenderMaskAndDepth(benchmark::State& state) { render(state, 640, 480, false, 1.0, false); }
void BM_RenderMaskAndDepthDistorted(benchmark::State& state) { render(state, 640, 480, true, 1.0, false); }
void BM_RenderMaskAndDepthSeabed(benchmark::State& state) { render(state, 640, 480, false, 1.0, true); }
void BM_RenderMaskAndDepthClose(benchmark::State& state) { render(state, 640, 480, false, 0.3, false); }
void BM_RenderMaskAndDepth720p(benchmark::State& state) { render(state, 1280, 720, true, 1.0, false); }
BENCHMARK(BM_RenderMaskAndDepth)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RenderMaskAndDepthDistorted)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RenderMaskAndDepthSeabed)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RenderMaskAndDepthClose)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RenderMaskAndDepth720p)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RenderMaskAndDepth720pBesideLens)->Unit(benchmark::kMicrosecond);

/// For comparison: the mask alone drawn the usual OpenCV way, cv::projectPoints then one cv::line per
/// segment as thick as f d / Z at its middle (no depth, no clipping: the arch is all in front). Integer
/// widths and no depth image, so it cannot meet the 1 px and 1 mm bounds; this is what it costs.
void BM_OpenCvLinesMaskOnly(benchmark::State& state)
{
  const CameraIntrinsics c = intrinsics(640, 480, false);
  const std::vector<Position> points = arch();
  std::vector<cv::Point3d> object;
  for (const auto& p : points)
  {
    object.emplace_back(p.x(), p.y(), p.z());
  }
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(c.K.data()));
  cv::Mat mask(c.height, c.width, CV_8UC1);
  std::vector<cv::Point2d> pixels;
  for (auto _ : state)
  {
    mask.setTo(0);
    cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cv::noArray(), pixels);
    for (std::size_t i = 0; i + 1 < pixels.size(); ++i)
    {
      const double z = 0.5 * (object[i].z + object[i + 1].z);
      const int thickness = std::max(1, static_cast<int>(std::lround(c.K[0] * 0.02 / z)));
      cv::line(mask, pixels[i], pixels[i + 1], cv::Scalar(255), thickness, cv::LINE_8);
    }
    benchmark::DoNotOptimize(mask.data);
  }
}
BENCHMARK(BM_OpenCvLinesMaskOnly)->Unit(benchmark::kMicrosecond);

/// Projection of 1,000 points with plumb_bob distortion: CameraModel::toPixel against cv::projectPoints.
void BM_ProjectOwn(benchmark::State& state)
{
  const CameraModel camera(intrinsics(640, 480, true));
  const std::vector<Position> points = arch();
  for (auto _ : state)
  {
    double sum = 0.0;
    for (int k = 0; k < 10; ++k)
    {
      for (const auto& p : points)
      {
        sum += camera.project(p).x();
      }
    }
    benchmark::DoNotOptimize(sum);
  }
}
void BM_ProjectOpenCv(benchmark::State& state)
{
  const CameraIntrinsics c = intrinsics(640, 480, true);
  std::vector<cv::Point3d> object;
  for (int k = 0; k < 10; ++k)
  {
    for (const auto& p : arch())
    {
      object.emplace_back(p.x(), p.y(), p.z());
    }
  }
  const cv::Mat K(3, 3, CV_64F, const_cast<double*>(c.K.data()));
  const cv::Mat D(c.D, true);
  std::vector<cv::Point2d> pixels;
  for (auto _ : state)
  {
    cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, pixels);
    benchmark::DoNotOptimize(pixels.data());
  }
}
BENCHMARK(BM_ProjectOwn)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProjectOpenCv)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
