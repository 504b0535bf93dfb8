#pragma once
/**
 * Obstacles a tether lies on or wraps around: a sphere, box, cylinder, capsule, plane or triangle mesh,
 * placed by a pose. The one question the contact asks of an obstacle is how deep a capsule (a cable segment
 * of the cable's radius) sits in it, where, and which way out (Obstacle::push). Primitives answer in closed
 * form here; meshes (loaded through assimp, queried through FCL) live in rov_tether_geometry
 * (mesh_obstacle.hpp), as does makeObstacle, which builds any of them from an ObstacleSpec.
 */

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/status.hpp"

namespace rov_tether
{

enum class ShapeType
{
  Sphere,
  Box,
  Cylinder,
  Capsule,
  Plane,
  Mesh
};

/// "sphere", "box", ... for a ShapeType; parseShapeType returns false for an unknown name.
const char* shapeTypeName(ShapeType type);
bool parseShapeType(const std::string& name, ShapeType* type);

/// One entry of the `obstacles` list (node, scenario and runner alike); docs/node.md "Obstacles and topology".
struct ObstacleSpec
{
  std::string name;
  ShapeType type = ShapeType::Sphere;
  Position position = Position::Zero();                   ///< [m], in the world frame (the node: in `frame`).
  Eigen::Vector3d orientation = Eigen::Vector3d::Zero();  ///< roll, pitch, yaw [rad] (fixed axes x, y, z).
  double radius = 0.0;                                    ///< sphere, cylinder, capsule [m].
  double length = 0.0;                                    ///< cylinder and capsule, along their local z [m].
  Eigen::Vector3d size = Eigen::Vector3d::Zero();         ///< box, full edge lengths [m].
  std::string file;                                       ///< mesh: STL, OBJ or DAE.
  double scale = 1.0;                                     ///< mesh: its units to metres [-].
  double friction = 0.5;                                  ///< Coulomb coefficient [-].
  std::string frame;                                      ///< node only: the tf frame it moves with.
};

/// Refuses an entry whose name is empty, holds a comma, a double quote or a control character (a field of the
/// runner's topology.csv) or is not UTF-8 (text in Python and in the node's messages), whose numbers are not finite,
/// whose sizes are not positive, whose friction is outside [0, 10] or a mesh without a file; the message names the
/// obstacle and the field.
Status validate(const ObstacleSpec& spec);

/// An axis-aligned box [m].
struct Aabb
{
  Position lo = Position::Constant(std::numeric_limits<double>::infinity());
  Position hi = Position::Constant(-std::numeric_limits<double>::infinity());

  bool overlaps(const Aabb& o) const
  {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
  void grow(const Position& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
  void inflate(double margin) { lo.array() -= margin, hi.array() += margin; }
};

/// Where a capsule sits in an obstacle: the point at parameter t of the segment [a, b] (0 at a) is depth
/// deep, and moving it by depth along normal (unit, pointing out of the obstacle) clears it.
struct Push
{
  double t = 0.0;
  double u = 0.0;      ///< Capsule against capsule: where along the other one [-].
  double depth = 0.0;  ///< [m], > 0.
  Position normal = Position::UnitZ();
};

class Obstacle
{
 public:
  explicit Obstacle(const ObstacleSpec& spec);
  virtual ~Obstacle() = default;

  const std::string& name() const { return spec_.name; }
  const ObstacleSpec& spec() const { return spec_; }
  double friction() const { return spec_.friction; }
  /// Moves the obstacle (the node: when its tf frame moves).
  void setPose(const Position& position, const Eigen::Quaterniond& orientation);
  const Eigen::Isometry3d& pose() const { return pose_; }
  /// Box, cylinder, capsule: their local z through their centre, the axis wraps are counted around.
  bool hasAxis() const
  {
    return spec_.type == ShapeType::Box || spec_.type == ShapeType::Cylinder || spec_.type == ShapeType::Capsule;
  }
  Position axisPoint() const { return pose_.translation(); }
  Position axisDirection() const { return pose_.linear().col(2); }
  /// World bounds (a plane: a box reaching far along it).
  virtual Aabb bounds() const = 0;
  /// Whether the capsule [a, b] of `radius` overlaps the obstacle, and if so where and how to clear it
  /// (the deepest point). Must not allocate.
  virtual bool push(const Position& a, const Position& b, double radius, Push* out) const = 0;
  /// What an obstacle may keep between queries of one cable segment, which moves little from one to the
  /// next: a mesh keeps the triangles near it (MeshObstacle::pushNear). One per segment, owned by the caller;
  /// the first mesh to fill it keeps it.
  struct Near
  {
    static constexpr int kCapacity = 16;
    const Obstacle* owner = nullptr;  ///< The obstacle that filled it.
    Aabb box;                         ///< In the owner's frame: what overlaps it is listed.
    std::array<std::uint32_t, kCapacity> items{};
    static constexpr int kEmpty = -1;    ///< Nothing kept.
    static constexpr int kTooMany = -2;  ///< More than kCapacity overlap `box`: none kept for it.
    int count = kEmpty;
  };
  /// push for a segment that keeps `near` from one query to the next: the same answer, found faster where
  /// the obstacle keeps something (a mesh); the others ignore it.
  virtual bool pushNear(const Position& a, const Position& b, double radius, Push* out, Near* /*near*/) const
  {
    return push(a, b, radius, out);
  }

 protected:
  /// Called after the pose changed.
  virtual void placed() {}
  ObstacleSpec spec_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
};

/// Parameters (s on [a, b], u on [c, d]) of the closest points of two segments (Ericson 2005, 5.1.9).
void closestSegmentParameters(const Position& a, const Position& b, const Position& c, const Position& d, double* s,
                              double* u);

/// The capsule [a, b] of `radius` against the capsule [c, d] of `other_radius` (a cable segment of another
/// tether, a capsule obstacle; a sphere when c = d): whether they overlap, and how to clear [a, b].
bool pushCapsule(const Position& a, const Position& b, double radius, const Position& c, const Position& d,
                 double other_radius, Push* out);

/// A sphere, box, cylinder, capsule or plane (the plane: its local z is its normal, it fills z < 0).
/// Refuses a mesh (makeObstacle in rov_tether_geometry builds those) and an invalid spec.
std::unique_ptr<Obstacle> makePrimitive(const ObstacleSpec& spec, Status* status);

}  // namespace rov_tether
