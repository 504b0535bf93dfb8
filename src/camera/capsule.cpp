#include "rov_tether/camera/capsule.hpp"

#include <algorithm>

namespace rov_tether::camera
{
namespace
{

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Narrows [lo, hi] to the lambdas with slope * lambda <= bound.
void keepBelow(double slope, double bound, double* lo, double* hi)
{
  if (slope > 0.0)
  {
    *hi = std::min(*hi, bound / slope);
  }
  else if (slope < 0.0)
  {
    *lo = std::max(*lo, bound / slope);
  }
  else if (bound < 0.0)
  {
    *lo = kInf;  // never
  }
}

}  // namespace

CapsuleFootprint::CapsuleFootprint(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r)
    : box_a_(ballBox(a, r)), box_b_(ballBox(b, r))
{
  // A ray d = (x, y, 1) passes within r of the axis line {a + s w} when (d . m)^2 <= r^2 |d x w|^2,
  // m = w x a, and |d x w|^2 = |d|^2 |w|^2 - (d . w)^2.
  const Eigen::Vector3d w = b - a;
  const Eigen::Vector3d m = w.cross(a);
  const double r2 = r * r, ww = w.squaredNorm();
  q_xx_ = r2 * (ww - w.x() * w.x()) - m.x() * m.x();
  q_xy_ = -2.0 * (r2 * w.x() * w.y() + m.x() * m.y());
  q_yy_ = r2 * (ww - w.y() * w.y()) - m.y() * m.y();
  q_x_ = -2.0 * (r2 * w.x() * w.z() + m.x() * m.z());
  q_y_ = -2.0 * (r2 * w.y() * w.z() + m.y() * m.z());
  q_1_ = r2 * (ww - w.z() * w.z()) - m.z() * m.z();
}

CapsuleFootprint::Box CapsuleFootprint::ballBox(const Eigen::Vector3d& centre, double r)
{
  // The planes x = s z through the camera tangent to the ball: (c_x - s c_z)^2 = r^2 (1 + s^2).
  const double zz = centre.z() * centre.z() - r * r;
  const auto extent = [&](double cx, double* lo, double* hi)
  {
    const double root = r * std::sqrt(std::max(cx * cx + zz, 0.0));
    *lo = (cx * centre.z() - root) / zz;
    *hi = (cx * centre.z() + root) / zz;
  };
  Box box{};
  extent(centre.x(), &box.x_lo, &box.x_hi);
  extent(centre.y(), &box.y_lo, &box.y_hi);
  return box;
}

XRange CapsuleFootprint::wedgeAt(double y) const
{
  if (!(q_xx_ < 0.0))
  {
    return {-kInf, kInf};  // the wedge holds horizontal lines (or the camera is inside the cylinder)
  }
  const double b = q_xy_ * y + q_x_;
  const double c = (q_yy_ * y + q_y_) * y + q_1_;
  // The form is degenerate (two lines): the discriminant is a square, >= 0 but for rounding.
  const double root = std::sqrt(std::max(b * b - 4.0 * q_xx_ * c, 0.0));
  const double x1 = (-b + root) / (2.0 * q_xx_), x2 = (-b - root) / (2.0 * q_xx_);
  return {std::min(x1, x2), std::max(x1, x2)};
}

XRange CapsuleFootprint::xRange(double y_lo, double y_hi) const
{
  // The hull of the boxes: points l p + (1 - l) q, p in box a, q in box b, l in [0, 1], whose y can be in
  // [y_lo, y_hi]; their x runs between the boxes' edges mixed by the smallest and largest such l.
  double l_lo = 0.0, l_hi = 1.0;
  keepBelow(box_a_.y_lo - box_b_.y_lo, y_hi - box_b_.y_lo, &l_lo, &l_hi);
  keepBelow(box_b_.y_hi - box_a_.y_hi, box_b_.y_hi - y_lo, &l_lo, &l_hi);
  if (!(l_lo <= l_hi))
  {
    return {kInf, -kInf};
  }
  const auto mix = [](double l, double p, double q) { return l * p + (1.0 - l) * q; };
  XRange range{std::min(mix(l_lo, box_a_.x_lo, box_b_.x_lo), mix(l_hi, box_a_.x_lo, box_b_.x_lo)),
               std::max(mix(l_lo, box_a_.x_hi, box_b_.x_hi), mix(l_hi, box_a_.x_hi, box_b_.x_hi))};
  // The wedge: its edges are lines, so its x extent over the band is that at the band's edges.
  const XRange at_lo = wedgeAt(y_lo), at_hi = wedgeAt(y_hi);
  range.lo = std::max(range.lo, std::min(at_lo.lo, at_hi.lo));
  range.hi = std::min(range.hi, std::max(at_lo.hi, at_hi.hi));
  return range;
}

}  // namespace rov_tether::camera
