#pragma once
// A tube segment seen from a camera: which rays hit it and how deep (CapsuleRay), and where on the image
// those rays can be (CapsuleFootprint), so that the renderer tests only the pixels of a tight per-row span.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether::camera
{

/**
 * Depth of the first hit of the ray t (x, y, 1), t > 0, on a capsule: the points within `r` of the segment
 * from a to b, in the optical frame (Quilez's ray-capsule intersection with a direction that is not
 * normalised, so t is the depth along the optical axis). The cylinder's hit is computed in the form
 * c / (-k1 + sqrt(h)), which keeps its digits when the ray grazes the tube or runs along it.
 */
struct CapsuleRay
{
  static constexpr double kMiss = std::numeric_limits<double>::infinity();

  CapsuleRay(const Eigen::Vector3d& a_in, const Eigen::Vector3d& b_in, double r)
      : a(a_in), b(b_in), ba(b_in - a_in), baba(ba.squaredNorm()), baoa(-ba.dot(a_in)), r2(r * r)
  {
    c = baba * a.squaredNorm() - baoa * baoa - r2 * baba;
    cap_a = a.squaredNorm() - r2;
    cap_b = b.squaredNorm() - r2;
  }

  /// +inf when the ray misses.
  double hit(double x, double y) const
  {
    const double dd = x * x + y * y + 1.0;
    const double bard = ba.x() * x + ba.y() * y + ba.z();
    const double rdoa = -(a.x() * x + a.y() * y + a.z());
    const double k2 = baba * dd - bard * bard;
    const double k1 = baba * rdoa - baoa * bard;
    const double h = k1 * k1 - k2 * c;
    if (h < 0.0)
    {
      return kMiss;  // misses the infinite cylinder, and so the capsule inside it
    }
    // The nearer root of k2 t^2 + 2 k1 t + c = 0; k1 < 0 when the axis is in front along the ray.
    const double q = -k1 + std::sqrt(h);
    if (q > 0.0 && c > 0.0)
    {
      const double t = c / q;
      const double along = baoa + t * bard;
      if (along > 0.0 && along < baba)
      {
        return t;
      }
    }
    // The round ends: the nearer hit of the two balls (the first hit of a union is the nearest).
    return std::min(ball(a, cap_a, x, y, dd), ball(b, cap_b, x, y, dd));
  }

  static double ball(const Eigen::Vector3d& centre, double cc, double x, double y, double dd)
  {
    const double dc = centre.x() * x + centre.y() * y + centre.z();
    const double disc = dc * dc - dd * cc;
    if (disc < 0.0)
    {
      return kMiss;
    }
    const double t = (dc - std::sqrt(disc)) / dd;
    return t > 0.0 ? t : kMiss;
  }

  Eigen::Vector3d a, b, ba;
  double baba, baoa, r2, c = 0.0, cap_a = 0.0, cap_b = 0.0;
};

/// An interval of normalised x (x / z); empty when lo > hi.
struct XRange
{
  double lo, hi;
  bool empty() const { return !(lo <= hi); }
};

/**
 * Where on the normalised image plane (x / z, y / z) the rays that hit a capsule can lie, both ends at
 * z > r: inside the convex hull of the two balls' images (the capsule is the hull of its balls, and a
 * perspective view keeps hulls of what lies in front), bounded here by the hull of the balls' exact
 * bounding boxes, and inside the wedge of rays that pass within r of the axis line (the infinite
 * cylinder, which holds the capsule; its quadratic form vanishes on the axis' direction, so its edges are
 * two lines). xRange gives, for a band of y, an interval of x holding every hitting ray in the band.
 */
class CapsuleFootprint
{
 public:
  CapsuleFootprint(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r);

  /// The y and x extents of the footprint (the hull of the balls' boxes).
  double yMin() const { return std::min(box_a_.y_lo, box_b_.y_lo); }
  double yMax() const { return std::max(box_a_.y_hi, box_b_.y_hi); }
  double xMin() const { return std::min(box_a_.x_lo, box_b_.x_lo); }
  double xMax() const { return std::max(box_a_.x_hi, box_b_.x_hi); }

  /// An interval of x holding every ray (x, y, 1), y in [y_lo, y_hi], that hits the capsule.
  XRange xRange(double y_lo, double y_hi) const;

 private:
  struct Box
  {
    double x_lo, x_hi, y_lo, y_hi;
  };
  /// The exact bounding box of the image of the ball (centre, r), centre.z() > r.
  static Box ballBox(const Eigen::Vector3d& centre, double r);
  /// The x interval of the rays within r of the axis line at height y (whole line when unbounded).
  XRange wedgeAt(double y) const;

  Box box_a_, box_b_;
  /// The wedge's quadratic form in (x, y): q_xx x^2 + q_xy x y + q_yy y^2 + q_x x + q_y y + q_1 >= 0.
  double q_xx_, q_xy_, q_yy_, q_x_, q_y_, q_1_;
};

}  // namespace rov_tether::camera
