#include "rov_tether/camera/camera_model.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>
#include <string>

#include "rov_tether/core/status.hpp"

namespace rov_tether::camera
{
namespace
{

/// The first index in [lo, hi) where `holds` does (hi when none); `holds` is false, then true.
template <typename Predicate>
int firstWhere(int lo, int hi, Predicate holds)
{
  while (lo < hi)
  {
    const int mid = lo + (hi - lo) / 2;
    if (holds(mid))
    {
      hi = mid;
    }
    else
    {
      lo = mid + 1;
    }
  }
  return lo;
}

/// Throws CameraBuildAbandoned when `abandoned` is given and says so.
void stopIfAbandoned(const BuildAbandoned& abandoned)
{
  if (abandoned && abandoned())
  {
    throw CameraBuildAbandoned();
  }
}

}  // namespace

CameraModel::CameraModel(const CameraIntrinsics& intrinsics, const BuildAbandoned& abandoned)
    : intrinsics_(intrinsics), d_(intrinsics.plumbBob())
{
  const auto errors = intrinsics_.validate();
  if (!errors.empty())
  {
    throw std::invalid_argument(joinMessages(errors));
  }
  max_focal_ = std::max(intrinsics_.fx(), intrinsics_.fy()) + std::abs(intrinsics_.skew());
  computeRays(abandoned);
  stopIfAbandoned(abandoned);
  computeRowTables();
}

Eigen::Vector2d CameraModel::toPixel(double x, double y) const
{
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d_[0] + r2 * (d_[1] + r2 * d_[4]));
  const double xd = x * radial + 2.0 * d_[2] * x * y + d_[3] * (r2 + 2.0 * x * x);
  const double yd = y * radial + d_[2] * (r2 + 2.0 * y * y) + 2.0 * d_[3] * x * y;
  const auto& K = intrinsics_.K;
  return {K[0] * xd + K[1] * yd + K[2], K[4] * yd + K[5]};
}

void CameraModel::computeRays(const BuildAbandoned& abandoned)
{
  const int w = width();
  const int h = height();
  const std::size_t n = static_cast<std::size_t>(w) * h;
  rays_.resize(2 * n);
  const auto& K = intrinsics_.K;
  if (!intrinsics_.distorted())
  {
    for (int v = 0; v < h; ++v)
    {
      const double y = (v - K[5]) / K[4];
      for (int u = 0; u < w; ++u)
      {
        float* r = &rays_[2 * (static_cast<std::size_t>(v) * w + u)];
        r[0] = static_cast<float>((u - K[2] - K[1] * y) / K[0]);
        r[1] = static_cast<float>(y);
      }
    }
  }
  else
  {
    // OpenCV inverts the distortion iteratively; enough iterations to converge to 1e-12 over the image.
    std::vector<cv::Point2d> pixels(n);
    for (int v = 0; v < h; ++v)
    {
      for (int u = 0; u < w; ++u)
      {
        pixels[static_cast<std::size_t>(v) * w + u] = cv::Point2d(u, v);
      }
    }
    std::vector<cv::Point2d> normalised(n);
    const cv::Mat k_mat(3, 3, CV_64F, const_cast<double*>(K.data()));
    const cv::Mat d_mat(1, 5, CV_64F, d_.data());
    // A stretch of rows at a time, each pixel on its own as in one call, so that `abandoned` is heard within one.
    for (int first = 0; first < h; first += kRowsPerStretch)
    {
      stopIfAbandoned(abandoned);
      const int rows = std::min(kRowsPerStretch, h - first);
      const cv::Mat in(rows * w, 1, CV_64FC2, &pixels[static_cast<std::size_t>(first) * w]);
      cv::Mat out(rows * w, 1, CV_64FC2, &normalised[static_cast<std::size_t>(first) * w]);
      cv::undistortPoints(in, out, k_mat, d_mat, cv::noArray(), cv::noArray(),
                          cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-14));
    }
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      rays_[2 * i] = static_cast<float>(normalised[i].x);
      rays_[2 * i + 1] = static_cast<float>(normalised[i].y);
      const Eigen::Vector2d back = toPixel(normalised[i].x, normalised[i].y);
      worst = std::max(worst, std::hypot(back.x() - pixels[i].x, back.y() - pixels[i].y));
    }
    if (!(worst < 0.01))
    {
      throw std::invalid_argument("D: the distortion cannot be inverted over the image (a pixel's ray maps back " +
                                  std::to_string(worst) + " px away): the radial distortion folds over");
    }
  }
  bounds_ = {rays_[0], rays_[0], rays_[1], rays_[1]};
  for (std::size_t i = 0; i < n; ++i)
  {
    bounds_.x_min = std::min<double>(bounds_.x_min, rays_[2 * i]);
    bounds_.x_max = std::max<double>(bounds_.x_max, rays_[2 * i]);
    bounds_.y_min = std::min<double>(bounds_.y_min, rays_[2 * i + 1]);
    bounds_.y_max = std::max<double>(bounds_.y_max, rays_[2 * i + 1]);
  }
  if (intrinsics_.distorted())
  {
    // Each pixel has one ray only if the distortion does not fold over within the image's rays: the radial
    // factor r (1 + k1 r^2 + k2 r^4 + k3 r^6) must grow monotonically out to the bounds' farthest corner.
    const double r_max = std::sqrt(std::max(bounds_.x_min * bounds_.x_min, bounds_.x_max * bounds_.x_max) +
                                   std::max(bounds_.y_min * bounds_.y_min, bounds_.y_max * bounds_.y_max));
    for (int i = 0; i <= 1000; ++i)
    {
      const double r2 = std::pow(r_max * i / 1000.0, 2);
      const double slope = 1.0 + r2 * (3.0 * d_[0] + r2 * (5.0 * d_[1] + r2 * 7.0 * d_[4]));
      if (!(slope > 0.0))
      {
        throw std::invalid_argument("D: the radial distortion folds over at a normalised radius of " +
                                    std::to_string(std::sqrt(r2)) + ", within the image's rays (up to " +
                                    std::to_string(r_max) + ")");
      }
    }
  }
}

void CameraModel::computeRowTables()
{
  const int w = width();
  const int h = height();
  blocks_ = (w + kBandColumns - 1) / kBandColumns;
  row_y_.assign(2 * static_cast<std::size_t>(h), 0.0);
  block_y_.assign(2 * static_cast<std::size_t>(h) * blocks_, 0.0f);
  rows_sorted_ = true;
  for (int v = 0; v < h; ++v)
  {
    const float* row = &rays_[2 * static_cast<std::size_t>(v) * w];
    float* blocks = &block_y_[2 * static_cast<std::size_t>(v) * blocks_];
    for (int u = 0; u < w; ++u)
    {
      float* block = &blocks[2 * (u / kBandColumns)];
      const float y = row[2 * u + 1];
      block[0] = u % kBandColumns == 0 ? y : std::min(block[0], y);
      block[1] = u % kBandColumns == 0 ? y : std::max(block[1], y);
      rows_sorted_ = rows_sorted_ && (u == 0 || row[2 * u] > row[2 * u - 2]);
    }
    row_y_[2 * v] = *std::min_element(blocks, blocks + 2 * blocks_);
    row_y_[2 * v + 1] = *std::max_element(blocks, blocks + 2 * blocks_);
  }
  bands_sorted_ = true;
  for (int v = 1; v < h; ++v)
  {
    bands_sorted_ = bands_sorted_ && rowYMin(v) >= rowYMin(v - 1) && rowYMax(v) >= rowYMax(v - 1);
  }
}

std::pair<double, double> CameraModel::rowYBetween(int v, int first, int last) const
{
  const float* blocks = &block_y_[2 * static_cast<std::size_t>(v) * blocks_];
  float y_min = blocks[2 * (first / kBandColumns)], y_max = blocks[2 * (first / kBandColumns) + 1];
  for (int b = first / kBandColumns + 1; b <= last / kBandColumns; ++b)
  {
    y_min = std::min(y_min, blocks[2 * b]);
    y_max = std::max(y_max, blocks[2 * b + 1]);
  }
  return {y_min, y_max};
}

std::pair<int, int> CameraModel::rowsBetween(double y_lo, double y_hi) const
{
  if (!bands_sorted_)
  {
    return {0, height() - 1};
  }
  // The first row reaching y_lo, and the first one starting beyond y_hi.
  const int first = firstWhere(0, height(), [&](int v) { return rowYMax(v) >= y_lo; });
  const int past = firstWhere(first, height(), [&](int v) { return rowYMin(v) > y_hi; });
  return {first, past - 1};
}

std::pair<int, int> CameraModel::columnsBetween(int v, double x_lo, double x_hi, std::pair<int, int> near) const
{
  const int w = width();
  if (!rows_sorted_)
  {
    return {0, w - 1};
  }
  const float* row = &rays_[2 * static_cast<std::size_t>(v) * w];
  // The first column with x >= x_lo and the first with x > x_hi: by bisection, or by walking from `near`
  // (the answer for a neighbouring row: a few steps for a tube's consecutive rows).
  int first, past;
  if (near.first < 0 || near.first > w || near.second + 1 < 0 || near.second + 1 > w)
  {
    first = firstWhere(0, w, [&](int u) { return row[2 * u] >= x_lo; });
    past = firstWhere(first, w, [&](int u) { return row[2 * u] > x_hi; });
    return {first, past - 1};
  }
  first = near.first;
  while (first > 0 && row[2 * (first - 1)] >= x_lo)
  {
    --first;
  }
  while (first < w && row[2 * first] < x_lo)
  {
    ++first;
  }
  past = std::max(near.second + 1, first);
  while (past > first && row[2 * (past - 1)] > x_hi)
  {
    --past;
  }
  while (past < w && row[2 * past] <= x_hi)
  {
    ++past;
  }
  return {first, past - 1};
}

}  // namespace rov_tether::camera
