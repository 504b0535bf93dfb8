#include "rov_tether/core/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

namespace rov_tether
{
namespace
{

/// The length of the UTF-8 character that starts at text[i], or 0 when the bytes there are not one (a stray
/// continuation byte, a character cut short, an overlong form, a surrogate or beyond U+10FFFF): as Python decodes.
std::size_t utf8Length(const std::string& text, std::size_t i)
{
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  if (lead < 0x80)
  {
    return 1;
  }
  const std::size_t length = (lead & 0xe0) == 0xc0 ? 2 : (lead & 0xf0) == 0xe0 ? 3 : (lead & 0xf8) == 0xf0 ? 4 : 0;
  if (length == 0 || i + length > text.size())
  {
    return 0;
  }
  std::uint32_t code = lead & (0x7f >> length);
  for (std::size_t k = 1; k < length; ++k)
  {
    if ((byte(i + k) & 0xc0) != 0x80)
    {
      return 0;
    }
    code = code << 6 | (byte(i + k) & 0x3f);
  }
  const std::uint32_t least = length == 2 ? 0x80 : length == 3 ? 0x800 : 0x10000;
  return code < least || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff) ? 0 : length;
}

/// A unit vector perpendicular to v (v not zero).
Position perpendicular(const Position& v)
{
  const Position p = std::abs(v.x()) < 0.9 ? v.cross(Position::UnitX()) : v.cross(Position::UnitY());
  return p.normalized();
}

/// A capsule of `radius` against a core segment [c, d] of `core_radius` (a sphere when c = d).
bool pushFromCore(const Position& a, const Position& b, double radius, const Position& c, const Position& d,
                  double core_radius, Push* out)
{
  double s = 0.0, u = 0.0;
  closestSegmentParameters(a, b, c, d, &s, &u);
  const Position q = a + s * (b - a);
  const Position k = c + u * (d - c);
  const Position gap = q - k;
  const double distance = gap.norm();
  const double reach = radius + core_radius;
  if (!(distance < reach))
  {
    return false;
  }
  out->t = s;
  out->u = u;
  out->depth = reach - distance;
  // On the core itself no side is defined: out across the segment and the core.
  out->normal = distance > 1e-12 * reach            ? Position(gap / distance)
                : (b - a).cross(d - c).norm() > 0.0 ? Position((b - a).cross(d - c).normalized())
                                                    : perpendicular(b - a + d - c + Position::UnitZ() * 1e-30);
  return true;
}

class SphereObstacle : public Obstacle
{
 public:
  using Obstacle::Obstacle;
  Aabb bounds() const override
  {
    Aabb box;
    box.grow(pose_.translation());
    box.inflate(spec_.radius);
    return box;
  }
  bool push(const Position& a, const Position& b, double radius, Push* out) const override
  {
    return pushFromCore(a, b, radius, pose_.translation(), pose_.translation(), spec_.radius, out);
  }
};

class CapsuleObstacle : public Obstacle
{
 public:
  using Obstacle::Obstacle;
  Aabb bounds() const override
  {
    Aabb box;
    box.grow(end(-1.0)), box.grow(end(1.0));
    box.inflate(spec_.radius);
    return box;
  }
  bool push(const Position& a, const Position& b, double radius, Push* out) const override
  {
    return pushFromCore(a, b, radius, end(-1.0), end(1.0), spec_.radius, out);
  }

 private:
  Position end(double sign) const { return pose_ * Position(0.0, 0.0, sign * 0.5 * spec_.length); }
};

/**
 * A convex shape known by its signed distance in its own frame. The signed distance of a convex set is a
 * convex function, so along a segment it has one minimum, which golden-section search finds; the capsule
 * overlaps when that minimum is below its radius.
 */
class ConvexSdfObstacle : public Obstacle
{
 public:
  using Obstacle::Obstacle;
  bool push(const Position& a, const Position& b, double radius, Push* out) const override
  {
    const Eigen::Isometry3d to_local = pose_.inverse();
    const Position la = to_local * a, lb = to_local * b;
    Position gradient;
    double lo = 0.0, hi = 1.0;
    constexpr double kGolden = 0.6180339887498949;
    double m1 = hi - kGolden * (hi - lo), m2 = lo + kGolden * (hi - lo);
    double f1 = distance(la + m1 * (lb - la), nullptr), f2 = distance(la + m2 * (lb - la), nullptr);
    // 48 iterations shrink the bracket to 1e-10 of the segment.
    for (int i = 0; i < 48; ++i)
    {
      if (f1 < f2)
      {
        hi = m2, m2 = m1, f2 = f1, m1 = hi - kGolden * (hi - lo), f1 = distance(la + m1 * (lb - la), nullptr);
      }
      else
      {
        lo = m1, m1 = m2, f1 = f2, m2 = lo + kGolden * (hi - lo), f2 = distance(la + m2 * (lb - la), nullptr);
      }
    }
    // The ends themselves, where the minimum of a monotone stretch lies.
    double t = 0.5 * (lo + hi);
    double best = distance(la + t * (lb - la), nullptr);
    for (double end : {0.0, 1.0})
    {
      const double at_end = distance(la + end * (lb - la), nullptr);
      if (at_end < best)
      {
        best = at_end, t = end;
      }
    }
    if (!(best < radius))
    {
      return false;
    }
    distance(la + t * (lb - la), &gradient);
    out->t = t;
    out->depth = radius - best;
    out->normal = pose_.linear() * gradient;
    return true;
  }

 protected:
  /// Signed distance of the local point p [m] and, when asked, its unit gradient (the way out).
  virtual double distance(const Position& p, Position* gradient) const = 0;
};

class BoxObstacle : public ConvexSdfObstacle
{
 public:
  using ConvexSdfObstacle::ConvexSdfObstacle;
  Aabb bounds() const override
  {
    Aabb box;
    const Position half = 0.5 * spec_.size;
    for (int corner = 0; corner < 8; ++corner)
    {
      box.grow(pose_ * Position((corner & 1) ? half.x() : -half.x(), (corner & 2) ? half.y() : -half.y(),
                                (corner & 4) ? half.z() : -half.z()));
    }
    return box;
  }

 protected:
  double distance(const Position& p, Position* gradient) const override
  {
    const Position half = 0.5 * spec_.size;
    const Position q = p.cwiseAbs() - half;
    const Position outside = q.cwiseMax(0.0);
    const double out_norm = outside.norm();
    if (out_norm > 0.0)
    {
      if (gradient != nullptr)
      {
        *gradient = (outside / out_norm).cwiseProduct(p.cwiseSign());
      }
      return out_norm;
    }
    Eigen::Index axis = 0;
    const double inside = q.maxCoeff(&axis);
    if (gradient != nullptr)
    {
      *gradient = Position::Zero();
      (*gradient)[axis] = p[axis] < 0.0 ? -1.0 : 1.0;
    }
    return inside;
  }
};

class CylinderObstacle : public ConvexSdfObstacle
{
 public:
  using ConvexSdfObstacle::ConvexSdfObstacle;
  Aabb bounds() const override
  {
    Aabb box;
    const Position axis = axisDirection();
    const Position ends[2] = {pose_ * Position(0.0, 0.0, -0.5 * spec_.length),
                              pose_ * Position(0.0, 0.0, 0.5 * spec_.length)};
    for (const Position& end : ends)
    {
      // A disc of radius R across `axis` reaches R sqrt(1 - axis_i^2) along world axis i.
      const Position reach = spec_.radius * (Position::Ones() - axis.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
      box.grow(end - reach), box.grow(end + reach);
    }
    return box;
  }

 protected:
  double distance(const Position& p, Position* gradient) const override
  {
    const double rho = std::hypot(p.x(), p.y());
    const double dr = rho - spec_.radius;
    const double dz = std::abs(p.z()) - 0.5 * spec_.length;
    const double zsign = p.z() < 0.0 ? -1.0 : 1.0;
    const Position radial = rho > 1e-15 ? Position(p.x() / rho, p.y() / rho, 0.0) : Position::UnitX();
    if (dr > 0.0 && dz > 0.0)
    {
      const double d = std::hypot(dr, dz);
      if (gradient != nullptr)
      {
        *gradient = (dr * radial + dz * zsign * Position::UnitZ()) / d;
      }
      return d;
    }
    if (dr > dz)
    {
      if (gradient != nullptr)
      {
        *gradient = radial;
      }
      return dr;
    }
    if (gradient != nullptr)
    {
      *gradient = zsign * Position::UnitZ();
    }
    return dz;
  }
};

class PlaneObstacle : public Obstacle
{
 public:
  using Obstacle::Obstacle;
  Aabb bounds() const override
  {
    // Far along the plane, down to its surface only on the side it faces.
    constexpr double kFar = 1e9;
    Aabb box;
    box.lo = Position::Constant(-kFar), box.hi = Position::Constant(kFar);
    const Position n = axisDirection();
    for (int i = 0; i < 3; ++i)
    {
      if (std::abs(n[i]) > 1.0 - 1e-12)
      {
        (n[i] > 0.0 ? box.hi : box.lo)[i] = pose_.translation()[i];
      }
    }
    return box;
  }
  bool push(const Position& a, const Position& b, double radius, Push* out) const override
  {
    const Position n = axisDirection();
    const double ha = n.dot(a - pose_.translation()), hb = n.dot(b - pose_.translation());
    const double low = std::min(ha, hb);
    if (!(low < radius))
    {
      return false;
    }
    out->t = ha < hb ? 0.0 : hb < ha ? 1.0 : 0.5;
    out->depth = radius - low;
    out->normal = n;
    return true;
  }
};

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

void closestSegmentParameters(const Position& a, const Position& b, const Position& c, const Position& d, double* s,
                              double* u)
{
  const Position e1 = b - a, e2 = d - c, r = a - c;
  const double aa = e1.squaredNorm(), ee = e2.squaredNorm(), f = e2.dot(r);
  constexpr double kTiny = 1e-24;
  if (aa <= kTiny && ee <= kTiny)
  {
    *s = *u = 0.0;
    return;
  }
  if (aa <= kTiny)
  {
    *s = 0.0, *u = std::clamp(f / ee, 0.0, 1.0);
    return;
  }
  const double cc = e1.dot(r);
  if (ee <= kTiny)
  {
    *u = 0.0, *s = std::clamp(-cc / aa, 0.0, 1.0);
    return;
  }
  const double bb = e1.dot(e2);
  const double denominator = aa * ee - bb * bb;
  double sv = denominator > kTiny * aa * ee ? std::clamp((bb * f - cc * ee) / denominator, 0.0, 1.0) : 0.0;
  double uv = (bb * sv + f) / ee;
  if (uv < 0.0)
  {
    uv = 0.0, sv = std::clamp(-cc / aa, 0.0, 1.0);
  }
  else if (uv > 1.0)
  {
    uv = 1.0, sv = std::clamp((bb - cc) / aa, 0.0, 1.0);
  }
  *s = sv, *u = uv;
}

bool pushCapsule(const Position& a, const Position& b, double radius, const Position& c, const Position& d,
                 double other_radius, Push* out)
{
  // Capsules whose boxes are apart do not touch: a few comparisons instead of the closest points (the grid
  // between tethers hands over many such pairs; bench_contact.cpp, BM_ContactWorldStep).
  const double reach = radius + other_radius;
  for (int k = 0; k < 3; ++k)
  {
    if (std::min(a[k], b[k]) - reach > std::max(c[k], d[k]) || std::min(c[k], d[k]) - reach > std::max(a[k], b[k]))
    {
      return false;
    }
  }
  return pushFromCore(a, b, radius, c, d, other_radius, out);
}

const char* shapeTypeName(ShapeType type)
{
  switch (type)
  {
    case ShapeType::Sphere:
      return "sphere";
    case ShapeType::Box:
      return "box";
    case ShapeType::Cylinder:
      return "cylinder";
    case ShapeType::Capsule:
      return "capsule";
    case ShapeType::Plane:
      return "plane";
    case ShapeType::Mesh:
      return "mesh";
  }
  return "?";
}

bool parseShapeType(const std::string& name, ShapeType* type)
{
  for (ShapeType t :
       {ShapeType::Sphere, ShapeType::Box, ShapeType::Cylinder, ShapeType::Capsule, ShapeType::Plane, ShapeType::Mesh})
  {
    if (name == shapeTypeName(t))
    {
      *type = t;
      return true;
    }
  }
  return false;
}

Status validate(const ObstacleSpec& spec)
{
  const std::string who = "obstacle '" + spec.name + "' (" + shapeTypeName(spec.type) + "): ";
  if (spec.name.empty())
  {
    return Status::error("obstacle: every obstacle needs a name");
  }
  // A field of topology.csv, written as it is (the earlier-outputs check reads the file back): no comma, quote or
  // line break (any control character) to split its row.
  if (std::any_of(spec.name.begin(), spec.name.end(),
                  [](char c) { return c == ',' || c == '"' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
  {
    std::string shown = spec.name;  // on one line
    std::replace_if(
        shown.begin(), shown.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }, '?');
    return Status::error("obstacle '" + shown + "' (" + shapeTypeName(spec.type) +
                         "): the name must hold no comma, double quote or control character (a field of the runner's "
                         "topology.csv)");
  }
  // Text that reaches Python (world.topology()) and the node's messages: UTF-8, as they read it.
  std::string shown;
  bool utf8 = true;
  for (std::size_t i = 0; i < spec.name.size();)
  {
    const std::size_t length = utf8Length(spec.name, i);
    utf8 = utf8 && length > 0;
    shown += length > 0 ? spec.name.substr(i, length) : "?";
    i += std::max<std::size_t>(length, 1);
  }
  if (!utf8)
  {
    return Status::error("obstacle '" + shown + "' (" + shapeTypeName(spec.type) +
                         "): the name must be UTF-8 text (each '?' is a byte that is not: a file saved in another "
                         "encoding?)");
  }
  if (!spec.position.allFinite() || !spec.orientation.allFinite())
  {
    return Status::error(who + "position and orientation must be finite");
  }
  if (!(spec.friction >= 0.0 && spec.friction <= 10.0))
  {
    return Status::error(who + "friction must be in [0, 10]");
  }
  const bool round =
      spec.type == ShapeType::Sphere || spec.type == ShapeType::Cylinder || spec.type == ShapeType::Capsule;
  if (round && !positive(spec.radius))
  {
    return Status::error(who + "radius must be > 0 m");
  }
  if ((spec.type == ShapeType::Cylinder || spec.type == ShapeType::Capsule) && !positive(spec.length))
  {
    return Status::error(who + "length must be > 0 m");
  }
  if (spec.type == ShapeType::Box && !(positive(spec.size.x()) && positive(spec.size.y()) && positive(spec.size.z())))
  {
    return Status::error(who + "size must be three lengths > 0 m");
  }
  if (spec.type == ShapeType::Mesh && spec.file.empty())
  {
    return Status::error(who + "a mesh needs a file (STL, OBJ or DAE)");
  }
  if (spec.type == ShapeType::Mesh && !positive(spec.scale))
  {
    return Status::error(who + "scale must be > 0");
  }
  return Status::success();
}

Obstacle::Obstacle(const ObstacleSpec& spec) : spec_(spec)
{
  const Eigen::Quaterniond q = Eigen::AngleAxisd(spec.orientation.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(spec.orientation.y(), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(spec.orientation.x(), Eigen::Vector3d::UnitX());
  pose_ = Eigen::Translation3d(spec.position) * q;
}

void Obstacle::setPose(const Position& position, const Eigen::Quaterniond& orientation)
{
  pose_ = Eigen::Translation3d(position) * orientation.normalized();
  placed();
}

std::unique_ptr<Obstacle> makePrimitive(const ObstacleSpec& spec, Status* status)
{
  Status check = validate(spec);
  std::unique_ptr<Obstacle> made;
  if (check)
  {
    switch (spec.type)
    {
      case ShapeType::Sphere:
        made = std::make_unique<SphereObstacle>(spec);
        break;
      case ShapeType::Box:
        made = std::make_unique<BoxObstacle>(spec);
        break;
      case ShapeType::Cylinder:
        made = std::make_unique<CylinderObstacle>(spec);
        break;
      case ShapeType::Capsule:
        made = std::make_unique<CapsuleObstacle>(spec);
        break;
      case ShapeType::Plane:
        made = std::make_unique<PlaneObstacle>(spec);
        break;
      case ShapeType::Mesh:
        check = Status::error("obstacle '" + spec.name + "': meshes are built by makeObstacle (rov_tether_geometry)");
        break;
    }
  }
  if (status != nullptr)
  {
    *status = check;
  }
  return made;
}

}  // namespace rov_tether
