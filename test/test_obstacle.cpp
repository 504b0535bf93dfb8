// Obstacles (contact issue): each primitive's push against its closed form, the spec checks, and the mesh
// obstacle (assimp + FCL): the shipped meshes load, a flat mesh pushes exactly as a plane, a closed hull
// pushes out through its front side, a seabed mesh holds a tether lying on it, bad files are clear errors.
//
// Tolerances. A closed form computed in doubles on lengths of at most ~40 m is good to a few ulps of 40 m
// (1e-14 m): kExact = 1e-12 m leaves a margin of 100. The box and cylinder find the deepest point by golden-
// section search, which brackets it to 1e-10 of the segment; the cases below put it at an end or where the
// distance is flat, so their depth is also exact to rounding; where it is not (kSearch), the depth is off by
// at most the slope (<= 1) times the bracket times the length (~4 m): 1e-9 m.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rov_tether/core/world.hpp"
#include "rov_tether/geometry/make_obstacle.hpp"
#include "rov_tether/geometry/mesh_obstacle.hpp"
#include "test_helpers.hpp"

namespace rov_tether::test
{
namespace
{

constexpr double kExact = 1e-12;  // [m] closed forms, rounding only (see above)
constexpr double kSearch = 1e-9;  // [m] golden-section bracket times slope and length (see above)
constexpr double kCable = 0.1;    // [m] capsule radius used by the push cases
const std::string kSource = ROV_TETHER_SOURCE_DIR;

std::unique_ptr<Obstacle> make(const ObstacleSpec& spec)
{
  Status status;
  std::unique_ptr<Obstacle> made = makeObstacle(spec, &status);
  EXPECT_TRUE(status.ok) << status.message;
  return made;
}

ObstacleSpec spec(ShapeType type)
{
  ObstacleSpec s;
  s.name = shapeTypeName(type);
  s.type = type;
  return s;
}

void expectNear(const Position& expected, const Position& actual, double tolerance)
{
  EXPECT_LT((expected - actual).norm(), tolerance)
      << "expected " << expected.transpose() << ", got " << actual.transpose();
}

TEST(Obstacle, SpherePushIsRPlusROfTheCableMinusTheDistance)
{
  ObstacleSpec s = spec(ShapeType::Sphere);
  s.position = Position(1.0, 2.0, 3.0);
  s.radius = 1.0;
  const auto sphere = make(s);
  // A horizontal segment passing h above the centre: its closest point is its middle (t = 0.5) at distance h.
  for (const double h : {0.3, 0.95, 1.05})
  {
    Push push;
    ASSERT_TRUE(sphere->push(s.position + Position(-2.0, 0.0, h), s.position + Position(2.0, 0.0, h), kCable, &push));
    EXPECT_NEAR(push.depth, s.radius + kCable - h, kExact);
    EXPECT_NEAR(push.t, 0.5, kExact);
    expectNear(Position::UnitZ(), push.normal, kExact);
  }
  // Out of reach: distance 1.2 > R + r = 1.1.
  Push push;
  EXPECT_FALSE(
      sphere->push(s.position + Position(-2.0, 0.0, 1.2), s.position + Position(2.0, 0.0, 1.2), kCable, &push));
  // A segment ending before the sphere: closest at its end (t = 1), distance to the centre |(−1.05, 0, 0)|.
  ASSERT_TRUE(
      sphere->push(s.position + Position(-3.0, 0.0, 0.0), s.position + Position(-1.05, 0.0, 0.0), kCable, &push));
  EXPECT_NEAR(push.depth, 1.0 + kCable - 1.05, kExact);
  EXPECT_NEAR(push.t, 1.0, kExact);
  expectNear(-Position::UnitX(), push.normal, kExact);
}

TEST(Obstacle, BoxFaceAndEdge)
{
  // A 2 x 4 x 6 m box turned 90 degrees about z: in the world it spans x in [-2, 2], y in [-1, 1], z in [-3, 3].
  ObstacleSpec s = spec(ShapeType::Box);
  s.size = Position(2.0, 4.0, 6.0);
  s.orientation = Position(0.0, 0.0, M_PI / 2);
  const auto box = make(s);
  const Aabb bounds = box->bounds();
  expectNear(Position(-2.0, -1.0, -3.0), bounds.lo, kExact);
  expectNear(Position(2.0, 1.0, 3.0), bounds.hi, kExact);
  Push push;
  // Face: a segment sloping down over the top face from 0.2 m to 0.02 m above it: deepest at its low end,
  // depth r - 0.02, out along +z.
  ASSERT_TRUE(box->push(Position(-1.5, 0.2, 3.2), Position(1.5, -0.2, 3.02), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.02, kExact);
  EXPECT_NEAR(push.t, 1.0, kExact);
  expectNear(Position::UnitZ(), push.normal, kExact);
  // The long side face (x = 2), a segment along z 0.05 m off it: depth r - 0.05, out along +x.
  ASSERT_TRUE(box->push(Position(2.05, 0.0, -1.0), Position(2.05, 0.0, 1.0), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.05, kExact);
  expectNear(Position::UnitX(), push.normal, kExact);
  // Edge (y = 1, z = 3, along x): a segment along x, 0.05 m off the edge on its diagonal. Closest point: the
  // edge, distance 0.05; the way out: the diagonal (0, 1, 1)/sqrt 2.
  const double off = 0.05 / std::sqrt(2.0);
  ASSERT_TRUE(box->push(Position(-1.0, 1.0 + off, 3.0 + off), Position(1.0, 1.0 + off, 3.0 + off), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.05, kExact);
  expectNear(Position(0.0, 1.0, 1.0) / std::sqrt(2.0), push.normal, kExact);
  // Across the edge diagonal 0.11 m off: beyond r.
  const double far = 0.11 / std::sqrt(2.0);
  EXPECT_FALSE(box->push(Position(-1.0, 1.0 + far, 3.0 + far), Position(1.0, 1.0 + far, 3.0 + far), kCable, &push));
}

TEST(Obstacle, CylinderSideAndCap)
{
  // Radius 1, length 4, its axis turned from z to -y (roll 90 degrees), centred at (0, 0, -5).
  ObstacleSpec s = spec(ShapeType::Cylinder);
  s.radius = 1.0;
  s.length = 4.0;
  s.position = Position(0.0, 0.0, -5.0);
  s.orientation = Position(M_PI / 2, 0.0, 0.0);
  const auto cylinder = make(s);
  expectNear(Position(0.0, -1.0, 0.0), cylinder->axisDirection(), kExact);
  Push push;
  // Side: a segment parallel to the axis, 1.05 from it (above): depth R + ... no, r - 0.05; out along +z.
  ASSERT_TRUE(cylinder->push(Position(0.0, -1.5, -3.95), Position(0.0, 1.5, -3.95), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.05, kExact);
  expectNear(Position::UnitZ(), push.normal, kExact);
  // Side, a chord across the axis direction: the distance from the axis sqrt(1.05^2 + s^2) is least at the
  // middle, where it is flat (so the search is exact to its bracket squared).
  ASSERT_TRUE(cylinder->push(Position(-2.0, 0.5, -3.95), Position(2.0, 0.5, -3.95), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.05, kSearch);
  EXPECT_NEAR(push.t, 0.5, 1e-4);  // sqrt(kSearch): the flat minimum pins t only to the root of the depth error
  expectNear(Position::UnitZ(), push.normal, 1e-4);
  // Cap (the end at y = -2): a segment across it, 0.03 m beyond it, inside its rim: depth r - 0.03, out -y.
  ASSERT_TRUE(cylinder->push(Position(-0.5, -2.03, -5.2), Position(0.5, -2.03, -4.8), kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.03, kExact);
  expectNear(-Position::UnitY(), push.normal, kExact);
}

TEST(Obstacle, CapsuleObstacleSideAndEnd)
{
  // Radius 0.5, length 2 (its core from z = -1 to z = 1), at the origin.
  ObstacleSpec s = spec(ShapeType::Capsule);
  s.radius = 0.5;
  s.length = 2.0;
  const auto capsule = make(s);
  Push push;
  // Side: a segment along x crossing 0.55 from the core: depth 0.5 + r - 0.55, at its middle, out along +y.
  ASSERT_TRUE(capsule->push(Position(-1.0, 0.55, 0.3), Position(1.0, 0.55, 0.3), kCable, &push));
  EXPECT_NEAR(push.depth, 0.5 + kCable - 0.55, kExact);
  EXPECT_NEAR(push.t, 0.5, kExact);
  expectNear(Position::UnitY(), push.normal, kExact);
  // End: a segment along x passing 0.58 above the top of the core (z = 1): the hemisphere, depth
  // 0.5 + r - 0.58, out along +z.
  ASSERT_TRUE(capsule->push(Position(-1.0, 0.0, 1.58), Position(1.0, 0.0, 1.58), kCable, &push));
  EXPECT_NEAR(push.depth, 0.5 + kCable - 0.58, kExact);
  expectNear(Position::UnitZ(), push.normal, kExact);
  // Off the end on the diagonal, 0.61 from the core's end: beyond 0.5 + r.
  EXPECT_FALSE(capsule->push(Position(-1.0, 0.61 / std::sqrt(2.0), 1.0 + 0.61 / std::sqrt(2.0)),
                             Position(1.0, 0.61 / std::sqrt(2.0), 1.0 + 0.61 / std::sqrt(2.0)), kCable, &push));
}

TEST(Obstacle, PlanePushesItsLowerEndUpAlongItsNormal)
{
  // A plane through (0, 0, -20) tilted 0.2 rad about x: normal (0, -sin 0.2, cos 0.2).
  ObstacleSpec s = spec(ShapeType::Plane);
  s.position = Position(0.0, 0.0, -20.0);
  s.orientation = Position(0.2, 0.0, 0.0);
  const auto plane = make(s);
  const Position n(0.0, -std::sin(0.2), std::cos(0.2));
  const Position tangent(1.0, 0.0, 0.0);
  Push push;
  // Ends 0.3 and 0.04 above it: depth r - 0.04 at t = 1.
  ASSERT_TRUE(plane->push(s.position + 0.3 * n, s.position + 2.0 * tangent + 0.04 * n, kCable, &push));
  EXPECT_NEAR(push.depth, kCable - 0.04, kExact);
  EXPECT_NEAR(push.t, 1.0, kExact);
  expectNear(n, push.normal, kExact);
  // An end 0.5 below it: depth r + 0.5 (a plane fills its back side).
  ASSERT_TRUE(plane->push(s.position - 0.5 * n, s.position + 2.0 * tangent + 0.04 * n, kCable, &push));
  EXPECT_NEAR(push.depth, kCable + 0.5, kExact);
  EXPECT_NEAR(push.t, 0.0, kExact);
  EXPECT_FALSE(plane->push(s.position + 0.3 * n, s.position + 2.0 * tangent + 0.1 * n, kCable, &push));
}

TEST(Obstacle, ValidateNamesTheObstacleAndTheField)
{
  struct Case
  {
    ObstacleSpec spec;
    const char* says;
  };
  std::vector<Case> cases;
  ObstacleSpec s = spec(ShapeType::Sphere);
  s.radius = 1.0;
  ASSERT_TRUE(validate(s).ok);
  cases.push_back({s, "needs a name"});
  cases.back().spec.name.clear();
  for (const char* bad : {"wreck,bow", "wreck\"", "wreck\nbow", "wreck\rbow", "wreck\tbow", "wreck\x01", "wreck\x7f"})
  {
    cases.push_back({s, "the name must hold no comma, double quote or control character"});
    cases.back().spec.name = bad;
  }
  cases.push_back({s, "radius"});
  cases.back().spec.radius = -1.0;
  cases.push_back({s, "friction"});
  cases.back().spec.friction = 11.0;
  cases.push_back({s, "finite"});
  cases.back().spec.position.x() = std::nan("");
  ObstacleSpec box = spec(ShapeType::Box);
  box.size = Position(1.0, 0.0, 1.0);
  cases.push_back({box, "size"});
  ObstacleSpec cylinder = spec(ShapeType::Cylinder);
  cylinder.radius = 1.0;
  cases.push_back({cylinder, "length"});
  ObstacleSpec mesh = spec(ShapeType::Mesh);
  cases.push_back({mesh, "needs a file"});
  mesh.file = kSource + "/meshes/wreck.stl";
  mesh.scale = 0.0;
  cases.push_back({mesh, "scale"});
  for (const Case& c : cases)
  {
    const Status status = validate(c.spec);
    EXPECT_FALSE(status.ok) << c.says;
    EXPECT_NE(status.message.find(c.says), std::string::npos) << status.message;
    if (!c.spec.name.empty())
    {
      // The name as given, a control character shown as '?' so that the message stays on one line.
      std::string shown = c.spec.name;
      std::replace_if(
          shown.begin(), shown.end(), [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; }, '?');
      EXPECT_NE(status.message.find("'" + shown + "'"), std::string::npos) << status.message;
      EXPECT_EQ(status.message.find_first_of("\n\r"), std::string::npos) << status.message;
    }
    Status made;
    EXPECT_EQ(makeObstacle(c.spec, &made), nullptr);
    EXPECT_FALSE(made.ok);
  }
  // A name is text in Python and in the node's messages: UTF-8 as Python decodes it, each byte that is not shown as
  // '?' (a Latin-1 letter, a character cut short, a stray continuation byte, an overlong '/', a surrogate, a code
  // point beyond U+10FFFF); UTF-8 beyond ASCII (2, 3 and 4 bytes, the last code point) is taken.
  for (const auto& [bad, shown] : std::vector<std::pair<std::string, std::string>>{{"pil\xe9r", "pil?r"},
                                                                                   {"wreck\xc3", "wreck?"},
                                                                                   {"\x80wreck", "?wreck"},
                                                                                   {"\xc0\xaf", "??"},
                                                                                   {"\xed\xa0\x80", "???"},
                                                                                   {"\xf4\x90\x80\x80", "????"}})
  {
    ObstacleSpec named = s;
    named.name = bad;
    const Status status = validate(named);
    EXPECT_FALSE(status.ok) << shown;
    EXPECT_NE(status.message.find("obstacle '" + shown + "' (sphere): the name must be UTF-8"), std::string::npos)
        << status.message;
  }
  for (const char* good : {"pilier \xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf"})
  {
    ObstacleSpec named = s;
    named.name = good;
    EXPECT_TRUE(validate(named).ok) << validate(named).message;
  }
}

TEST(MeshObstacle, BadFilesAreClearErrors)
{
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.name = "wreck";
  s.file = kSource + "/meshes/no_such_file.stl";
  Status status;
  EXPECT_EQ(makeObstacle(s, &status), nullptr);
  EXPECT_FALSE(status.ok);
  EXPECT_NE(status.message.find("'wreck'"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("no_such_file.stl"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("cannot be read"), std::string::npos) << status.message;
  // Text that is no mesh format.
  const std::string garbage = testing::TempDir() + "rov_tether_not_a_mesh.stl";
  std::ofstream(garbage) << "this is not a mesh\n";
  s.file = garbage;
  EXPECT_EQ(makeObstacle(s, &status), nullptr);
  EXPECT_FALSE(status.ok);
  EXPECT_NE(status.message.find(garbage), std::string::npos) << status.message;
  // An OBJ of points and a line: read, but no triangle.
  const std::string lines = testing::TempDir() + "rov_tether_lines.obj";
  std::ofstream(lines) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n";
  s.file = lines;
  EXPECT_EQ(makeObstacle(s, &status), nullptr);
  EXPECT_FALSE(status.ok);
  EXPECT_NE(status.message.find(lines), std::string::npos) << status.message;
  std::remove(garbage.c_str());
  std::remove(lines.c_str());
}

TEST(MeshObstacle, ShippedMeshesLoadScaledAndPlaced)
{
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.file = kSource + "/meshes/seabed.stl";
  const auto seabed = make(s);
  ASSERT_NE(seabed, nullptr);
  // scripts/make_meshes.py: 40 m x 40 m of 1 m cells, two triangles each; heights -20 m +- (0.5 + 0.3) m.
  EXPECT_EQ(dynamic_cast<const MeshObstacle&>(*seabed).triangleCount(), 3200u);
  const Aabb bed = seabed->bounds();
  EXPECT_NEAR(bed.lo.x(), -20.0, 1e-5);  // float32 in the file: 20 m to 2e-6 m
  EXPECT_NEAR(bed.hi.y(), 20.0, 1e-5);
  EXPECT_GT(bed.lo.z(), -20.8 - 1e-5);
  EXPECT_LT(bed.hi.z(), -19.2 + 1e-5);
  // The wreck: 6 m long, 2 m beam; at scale 2 and moved by (10, 0, -18), twice that around its new place.
  s.file = kSource + "/meshes/wreck.stl";
  s.scale = 2.0;
  s.position = Position(10.0, 0.0, -18.0);
  const auto wreck = make(s);
  ASSERT_NE(wreck, nullptr);
  const Aabb hull = wreck->bounds();
  EXPECT_NEAR(hull.lo.x(), 10.0 - 6.0, 1e-5);
  EXPECT_NEAR(hull.hi.x(), 10.0 + 6.0, 1e-5);
  EXPECT_NEAR(hull.hi.y() - hull.lo.y(), 2.0 * 2.0, 1e-5);
}

/// The distance from x to triangle (a, b, c) in the plane z = 0, written out the plain way (and not as the
/// mesh measures it): its height over the face when it stands over it, else its distance to the nearest
/// of the three edges (each the clamped projection onto the edge).
double distanceToFlatTriangle(const Position& x, const Position& a, const Position& b, const Position& c)
{
  const Position corners[3] = {a, b, c};
  bool over = true;
  double nearest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    const Position& e0 = corners[k];
    const Position edge = corners[(k + 1) % 3] - e0;
    over = over && edge.x() * (x.y() - e0.y()) - edge.y() * (x.x() - e0.x()) >= 0.0;  // left of a ccw edge
    const double s = std::clamp(edge.dot(x - e0) / edge.squaredNorm(), 0.0, 1.0);
    nearest = std::min(nearest, (x - (e0 + s * edge)).norm());
  }
  return over ? std::abs(x.z()) : nearest;
}

TEST(MeshObstacle, OneTrianglePushesByTheGapASampledSearchFinds)
{
  // One triangle, and segments in front of it in every direction over and around it (both ends above its
  // plane, up to 1.5 radii: the cases of a cable lying on a mesh, over a face, across an edge, past a
  // corner). The push is r minus the segment's distance to the triangle. Reference: the least distance of
  // 4001 points along the segment; the distance is 1-Lipschitz along it, so that overestimates by at most
  // half the spacing (0.3 m / 4000 / 2).
  const Position a(0.0, 0.0, 0.0), b(1.0, 0.0, 0.0), c(0.3, 0.8, 0.0);
  TriangleMesh mesh;
  mesh.vertices = {a, b, c};
  mesh.triangles.emplace_back(0, 1, 2);
  ObstacleSpec m = spec(ShapeType::Mesh);
  m.file = "(in memory)";
  const MeshObstacle one(m, mesh);
  const double length = 0.3, tolerance = 0.5 * length / 4000.0 + kExact;
  int touching = 0, near_edges = 0;
  for (int k = 0; k < 1000; ++k)
  {
    const double u = std::fmod(0.618034 * k, 1.0), v = std::fmod(0.414214 * k, 1.0), w = std::fmod(0.732051 * k, 1.0);
    const Position start(1.6 * u - 0.3, 1.4 * v - 0.3, kCable * (0.05 + 1.45 * w));
    const double heading = 7.0 * k, rise = 0.2 * kCable * std::sin(3.0 * k);
    Position end = start + length * Position(std::cos(heading), std::sin(heading), 0.0);
    end.z() = std::max(start.z() + rise, 0.05 * kCable);
    double reference = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 4000; ++i)
    {
      reference = std::min(reference, distanceToFlatTriangle(start + (i / 4000.0) * (end - start), a, b, c));
    }
    Push push;
    const bool hit = one.push(start, end, kCable, &push);
    if (std::abs(reference - kCable) > tolerance)
    {
      ASSERT_EQ(hit, reference < kCable) << k << ": reference gap " << reference;
    }
    if (hit)
    {
      ++touching;
      EXPECT_NEAR(push.depth, kCable - reference, tolerance) << k;
      const Position from = start + push.t * (end - start);
      near_edges += distanceToFlatTriangle(from, a, b, c) > std::abs(from.z()) + 1e-9 ? 1 : 0;
    }
  }
  std::printf("[ measured ] one triangle: %d of 1000 segments touch, %d across an edge or corner\n", touching,
              near_edges);
  // Coverage, not physics: many cases touch, and many of those across an edge or a corner, not only over
  // the face.
  EXPECT_GT(touching, 200);
  EXPECT_GT(near_edges, 50);
  // Through the face (the plane crossed inside the triangle): the lower end goes back to one radius in
  // front of it, a push of r minus its height (mesh_obstacle.hpp), whatever the culls and edges say.
  int through = 0;
  for (int k = 0; k < 1000; ++k)
  {
    const double u = std::fmod(0.618034 * k, 1.0), v = std::fmod(0.414214 * k, 1.0), w = std::fmod(0.732051 * k, 1.0);
    const Position start(1.6 * u - 0.3, 1.4 * v - 0.3, -kCable * (0.05 + 0.75 * w));
    const double heading = 7.0 * k;
    const Position end = start + Position(length * std::cos(heading), length * std::sin(heading),
                                          kCable * (0.1 + 2.0 * std::fmod(0.5 + 0.3819 * k, 1.0)));
    const Position crossing = start + (start.z() / (start.z() - end.z())) * (end - start);
    if (distanceToFlatTriangle(Position(crossing.x(), crossing.y(), 0.0), a, b, c) > 0.0 ||
        distanceToFlatTriangle(Position(crossing.x(), crossing.y(), 1e-6), a, b, c) > 1e-6 + 1e-12)
    {
      continue;  // crosses the plane outside the triangle (or on its edge): no closed form here
    }
    ++through;
    Push push;
    ASSERT_TRUE(one.push(start, end, kCable, &push)) << k;
    EXPECT_NEAR(push.depth, kCable - start.z(), kExact) << k;
    EXPECT_EQ(push.t, 0.0) << k;
    expectNear(Position::UnitZ(), push.normal, kExact);
  }
  EXPECT_GT(through, 100);  // coverage
}

TEST(MeshObstacle, AFlatMeshPushesExactlyAsAPlane)
{
  // The same pose for both: 5 m down, tilted 0.3 rad about x and 0.2 about y.
  ObstacleSpec s = spec(ShapeType::Plane);
  s.position = Position(1.0, -2.0, -5.0);
  s.orientation = Position(0.3, 0.2, 0.0);
  const auto plane = make(s);
  ObstacleSpec m = s;
  m.type = ShapeType::Mesh;
  m.name = "flat";
  m.file = "(in memory)";
  MeshObstacle mesh(m, flatMesh(20, 0.5));  // 10 m x 10 m, 800 triangles
  const Eigen::Isometry3d& pose = plane->pose();
  int touching = 0;
  // Segments of 0.3 m in every direction over the middle 6 m x 6 m, starting from 0.9 r below the surface
  // (within the mesh's reach: a mesh is a surface) to 1.2 r above it: every case the plane touches, the mesh must touch
  // with the same depth, point and normal, to rounding (both are closed forms: a height above the plane).
  for (int k = 0; k < 400; ++k)
  {
    const double u = std::fmod(0.618034 * k, 1.0), v = std::fmod(0.414214 * k, 1.0), w = std::fmod(0.732051 * k, 1.0);
    const Position start = pose * Position(6.0 * u - 3.0, 6.0 * v - 3.0, kCable * (2.1 * w - 0.9));
    const Position direction = Position(std::cos(7.0 * k), std::sin(7.0 * k), 0.8 * std::sin(3.0 * k)).normalized();
    const Position end = start + 0.3 * (pose.linear() * direction);
    Push expected, actual;
    const bool plane_hit = plane->push(start, end, kCable, &expected);
    const bool mesh_hit = mesh.push(start, end, kCable, &actual);
    ASSERT_EQ(plane_hit, mesh_hit) << k;
    if (!plane_hit)
    {
      continue;
    }
    ++touching;
    EXPECT_NEAR(actual.depth, expected.depth, kExact) << k;
    expectNear(expected.normal, actual.normal, kExact);
    if (std::abs(direction.z()) > 1e-6)  // a segment parallel to the plane has no single deepest point
    {
      EXPECT_NEAR(actual.t, expected.t, kExact) << k;
    }
  }
  EXPECT_GT(touching, 200);  // starts uniform over [-0.9 r, 1.2 r]: more than half touch
}

TEST(MeshObstacle, AClosedHullPushesOutThroughItsFront)
{
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.file = kSource + "/meshes/wreck.stl";
  const auto wreck = make(s);
  ASSERT_NE(wreck, nullptr);
  // A load of short segments 0.05 m outside and 0.05 m inside the hull over each of its triangles' centres:
  // the hull's own face is 0.05 away, so the depth is at least r - 0.05 (outside) or r + 0.05 (inside, from
  // behind: back out to its front), at most r + 0.05 + the hull's sagitta, and out is outward (dot > 0).
  TriangleMesh mesh;
  ASSERT_TRUE(loadTriangleMesh(s.file, 1.0, &mesh).ok);
  int checked = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); k += 7)
  {
    const Eigen::Vector3i& t = mesh.triangles[k];
    const Position& a = mesh.vertices[t[0]];
    const Position centre = (a + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
    const Position n = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).normalized();
    const Position along = n.cross(Position::UnitX()).norm() > 0.1 ? n.cross(Position::UnitX()).normalized()
                                                                   : n.cross(Position::UnitY()).normalized();
    for (const double side : {0.05, -0.05})
    {
      const Position p = centre + side * n;
      Push push;
      ASSERT_TRUE(wreck->push(p - 0.01 * along, p + 0.01 * along, kCable, &push)) << k;
      EXPECT_GE(push.depth, kCable - side - 1e-9) << k;
      EXPECT_GT(push.normal.dot(n), 0.0) << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

/// Height of the shipped seabed's triangulated surface at (x, y) [m]: scripts/make_meshes.py's heights at
/// the 1 m grid's corners, interpolated on the cell's triangle (cells split from (i, j) to (i + 1, j + 1)).
double seabedSurface(double x, double y)
{
  auto h = [](double gx, double gy)
  {
    return -20.0 + 0.5 * std::sin(2 * M_PI * gx / 17.0) * std::cos(2 * M_PI * gy / 13.0) +
           0.3 * std::sin(2 * M_PI * (gx + 0.5 * gy) / 9.0);
  };
  const double i = std::floor(x), j = std::floor(y), fx = x - i, fy = y - j;
  const double h00 = h(i, j), h10 = h(i + 1, j), h01 = h(i, j + 1), h11 = h(i + 1, j + 1);
  return fx >= fy ? h00 + fx * (h10 - h00) + fy * (h11 - h10) : h00 + fy * (h01 - h00) + fx * (h11 - h01);
}

TEST(MeshObstacle, WhatASegmentKeepsNearItGivesTheSameAnswer)
{
  // pushNear measures only the triangles it kept near the segment while the segment's box stays inside the
  // box they were kept for, and refills otherwise: every triangle that can touch is then among them, so it
  // answers as push does, bit for bit. A segment travels some 30 m over the rotated seabed, from half a
  // radius under the surface to two over it, by steps of up to 3 cm (many refills, more reuses).
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.file = kSource + "/meshes/seabed.stl";
  s.orientation = Position(0.0, 0.1, 0.3);
  const auto made = make(s);
  Obstacle::Near near;
  int reused = 0, hits = 0;
  Position centre(2.0, -3.0, 0.0);
  for (int k = 0; k < 2000; ++k)
  {
    // Round a circle of about 5 m over the 2000 steps, each 0 to 3 cm.
    centre += 0.03 * Position(std::cos(0.003 * k), std::sin(0.003 * k), 0.0) * std::fmod(0.618034 * k, 1.0);
    const double height = kCable * (2.5 * std::fmod(0.414214 * k, 1.0) - 0.5);
    const Position middle =
        made->pose() * Position(centre.x(), centre.y(), seabedSurface(centre.x(), centre.y()) + height);
    const Position half = 0.05 * made->pose().linear() * Position(std::cos(0.1 * k), std::sin(0.1 * k), 0.1);
    const Aabb kept = near.box;
    const int count = near.count;
    Push plain, kept_push;
    const bool plain_hit = made->push(middle - half, middle + half, kCable, &plain);
    ASSERT_EQ(made->pushNear(middle - half, middle + half, kCable, &kept_push, &near), plain_hit) << k;
    reused += count >= 0 && near.count == count && (near.box.lo == kept.lo) && (near.box.hi == kept.hi) ? 1 : 0;
    if (plain_hit)
    {
      ++hits;
      EXPECT_EQ(kept_push.depth, plain.depth) << k;
      EXPECT_EQ(kept_push.t, plain.t) << k;
      EXPECT_EQ(kept_push.normal, plain.normal) << k;
    }
  }
  // The walk touches the bed about half the time, and the kept triangles served most queries.
  EXPECT_GT(hits, 500);
  EXPECT_GT(reused, 1000);
}

TEST(MeshObstacle, ItsGridItsWalkOfTheTreeAndFclCollideAgree)
{
  // push finds triangles in its grid, pushThroughTree by walking FCL's tree, pushThroughFclCollide by asking
  // FCL's collide (GJK per triangle) which triangles the capsule overlaps; all then measure the same
  // triangles exactly. The grid and the tree filter conservatively and break ties by triangle number, so
  // they give the same answer, bit for bit, also for a cable resting on the surface at one radius to
  // rounding (whether that touches decides whether friction holds it). GJK decides overlap to its
  // tolerance (1e-6 m): against it, cases shallower than 1e-5 m may differ.
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.file = kSource + "/meshes/seabed.stl";
  s.orientation = Position(0.0, 0.1, 0.3);
  const auto made = make(s);
  const auto& seabed = dynamic_cast<const MeshObstacle&>(*made);
  int both = 0, resting = 0;
  for (int k = 0; k < 500; ++k)
  {
    const double u = std::fmod(0.618034 * k, 1.0), v = std::fmod(0.414214 * k, 1.0), w = std::fmod(0.732051 * k, 1.0);
    // Over the bed, from 0.5 r under the surface to 1.5 r over it (heights by the mesh's own closed form).
    const double x = 30.0 * u - 15.0, y = 30.0 * v - 15.0;
    const Position start = made->pose() * Position(x, y, seabedSurface(x, y) + kCable * (2.0 * w - 0.5));
    const Position end = start + 0.4 * Position(std::cos(5.0 * k), std::sin(5.0 * k), 0.3 * std::cos(11.0 * k));
    Push own, through_tree, through_fcl;
    const bool own_hit = seabed.push(start, end, kCable, &own);
    const bool fcl_hit = seabed.pushThroughFclCollide(start, end, kCable, &through_fcl);
    ASSERT_EQ(seabed.pushThroughTree(start, end, kCable, &through_tree), own_hit) << k;
    if (own_hit)
    {
      EXPECT_EQ(own.depth, through_tree.depth) << k;
      EXPECT_EQ(own.t, through_tree.t) << k;
      EXPECT_EQ(own.normal, through_tree.normal) << k;
    }
    // Resting on the surface, as a contact leaves it: a short segment half a radius into the bed, moved out
    // by the push it gets, sits at one radius from the bed to rounding.
    const Position in = made->pose() * Position(x, y, seabedSurface(x, y) + 0.5 * kCable);
    const Position short_end = in + 0.02 * (end - start);
    Push out_of_bed;
    ASSERT_TRUE(seabed.pushThroughTree(in, short_end, kCable, &out_of_bed)) << k;
    const Position moved = out_of_bed.depth * out_of_bed.normal;
    Push resting_grid, resting_tree;
    const bool resting_hit = seabed.push(in + moved, short_end + moved, kCable, &resting_grid);
    ASSERT_EQ(seabed.pushThroughTree(in + moved, short_end + moved, kCable, &resting_tree), resting_hit) << k;
    resting += resting_hit ? 1 : 0;
    if (resting_hit)
    {
      EXPECT_EQ(resting_grid.depth, resting_tree.depth) << k;
      EXPECT_EQ(resting_grid.normal, resting_tree.normal) << k;
    }
    if (own_hit && fcl_hit)
    {
      ++both;
      EXPECT_NEAR(own.depth, through_fcl.depth, kExact) << k;
      expectNear(through_fcl.normal, own.normal, kExact);
    }
    else
    {
      EXPECT_LT(own_hit ? own.depth : fcl_hit ? through_fcl.depth : 0.0, 1e-5) << k;
    }
  }
  EXPECT_GT(both, 250);  // starts uniform over [-0.5 r, 1.5 r]: more than half touch
  // At one radius to rounding, rounding decides whether a resting segment touches: both outcomes occur,
  // so the agreement above was tested on both sides of the edge.
  EXPECT_GT(resting, 0);
  EXPECT_LT(resting, 500);
}

/// `length` of heavy cable (1 N/m in water) all deployed, in segments of `segment`, locked winch, no noise.
TetherParams heavyCable(double length, double segment)
{
  TetherParams params;
  params.cable_length = length;
  params.initial_deployed_length = length;
  params.segment_length = segment;
  params.weight_in_water = 1.0;
  params.noise = 0.0;
  params.winch_mode = WinchMode::kLocked;
  return params;
}

/// Adds a tether of `params` to `world`, laid out straight up from `spool` (laid out slack between spool
/// and vehicle, it would hang through the seabed), whose vehicle comes down to `rest` over `seconds`,
/// easing in and out.
void addLoweredTether(World& world, const TetherParams& params, const Position& spool, const Position& rest,
                      double seconds)
{
  const Position above = spool + Position(0.0, 0.0, params.cable_length);
  ASSERT_TRUE(world.add("tether", std::make_unique<Tether>(params, spool, above)).ok);
  const int samples = static_cast<int>(std::lround(10.0 * seconds));
  for (int k = 1; k <= samples; ++k)
  {
    const double s = 0.5 - 0.5 * std::cos(3.14159265358979 * k / samples);
    ASSERT_TRUE(world.tether(world.size() - 1).addVehicleSample(0.1 * k, above + s * (rest - above)).ok);
  }
}

TEST(MeshObstacle, ATetherLyingOnTheShippedSeabedStaysOnIt)
{
  // 16 m of heavy cable (1 N/m in water) between two ends held 0.3 m over the seabed 12 m apart: it sinks
  // onto the rolling seabed (slopes up to 0.3 < friction 0.5, so it holds where it lands) and comes to rest.
  // It starts straight up from the spool (laid out slack between the two ends it would hang through the
  // swells), and the vehicle end comes down to its place over 8 s.
  ObstacleSpec s = spec(ShapeType::Mesh);
  s.name = "seabed";
  s.file = kSource + "/meshes/seabed.stl";
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(make(s));
  const TetherParams params = heavyCable(16.0, 0.2);
  const Position spool(-6.0, 1.0, seabedSurface(-6.0, 1.0) + 0.3), vehicle(6.0, 1.0, seabedSurface(6.0, 1.0) + 0.3);
  World world;
  world.setContactBetweenTethers(false);  // the seabed alone (and 5x faster)
  addLoweredTether(world, params, spool, vehicle, 8.0);
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  ASSERT_TRUE(world.advanceTo(20.0).ok);
  const double radius = 0.5 * params.diameter;
  auto heights = [&]()
  {
    std::vector<double> above;
    const Cable& cable = world.tether(0).state();
    for (std::size_t i = cable.first; i < cable.size(); ++i)
    {
      above.push_back(cable.z[i] - seabedSurface(cable.x[i], cable.y[i]));
    }
    return above;
  };
  const std::vector<double> at20 = heights();
  ASSERT_TRUE(world.advanceTo(25.0).ok);
  const std::vector<double> at25 = heights();
  int resting = 0;
  for (std::size_t i = 0; i < at25.size(); ++i)
  {
    // Never through it: the contact puts the cable's surface back on the seabed every sub-step, so what is
    // left is what one sub-step of sinking and the solver's stretch undo (well under the radius, 1 cm).
    EXPECT_GT(at25[i], 0.5 * radius) << i;
    // Lying on it (axis within 5 mm of one radius up), held by friction on slopes below mu: at rest, its
    // height moved less than a millimetre in the last 5 s. (The hanging ends may still sway.)
    if (at25[i] < radius + 0.005)
    {
      EXPECT_NEAR(at25[i], at20[i], 1e-3) << i;
      ++resting;
    }
  }
  // 16 m of cable over 12 m: at least the middle half lies on the seabed.
  EXPECT_GT(resting, static_cast<int>(at25.size()) / 2);
}

}  // namespace
}  // namespace rov_tether::test
namespace rov_tether::test
{
namespace
{
// 20 m of heavy cable with bending stiffness (the default 0.2 N m^2) lying on swells of 0.25 m triangles,
// 0.1 m segments: bent over the triangles' edges and held by friction, its segments carry a little
// compression, whose (negative) geometric stiffness the Newton step's Hessian needs. At rest the step
// starts within the contact's tolerance (5% of the radius) of its answer, and Newton with the exact
// Hessian converges quadratically from there: 2 iterations a step to the 1e-8 tolerance (an error of 1e-4
// of a segment squares to 1e-8). Without it in compression the convergence is linear, at the rate of the
// term left out (h^2 |T| w / L, about 1e-2 here), so the same start needs at least 3 (1e-4, 1e-6, 1e-8):
// 3.8 a step. Bound: half way between 2 and 3.
TEST(MeshObstacle, ATetherLyingOnSwellsTakesTwoNewtonIterationsAStep)
{
  TriangleMesh swells = flatMesh(160, 0.25);  // 40 m x 40 m
  for (Position& v : swells.vertices)
  {
    v.z() = 0.4 * std::sin(v.x() / 3.0) * std::cos(v.y() / 4.0);
  }
  ObstacleSpec m = spec(ShapeType::Mesh);
  m.name = "swells";
  m.file = "(in memory)";
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(std::make_unique<MeshObstacle>(m, swells));
  const TetherParams params = heavyCable(20.0, 0.1);
  // From a spool 4 m over the swells; the vehicle comes down to 0.3 m over them, 16 m away, over 6 s.
  World world;
  world.setContactBetweenTethers(false);
  addLoweredTether(world, params, Position(0.0, -8.0, 4.0), Position(0.5, 8.0, 0.3), 6.0);
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  ASSERT_TRUE(world.advanceTo(9.0).ok);
  int total = 0, lying = 0;
  for (int k = 1; k <= 400; ++k)
  {
    ASSERT_TRUE(world.advanceTo(9.0 + 0.005 * k).ok);
    total += world.tether(0).solverIterations();
  }
  const Tether& tether = world.tether(0);
  for (std::size_t i = 0; i < tether.deployedParticleCount(); ++i)
  {
    const Position p = tether.particle(i);
    lying += p.z() < 0.4 * std::sin(p.x() / 3.0) * std::cos(p.y() / 4.0) + 0.05 ? 1 : 0;
  }
  std::printf("[ measured ] %d of %zu particles on the swells; %.2f Newton iterations a step at rest\n", lying,
              tether.deployedParticleCount(), total / 400.0);
  ASSERT_GT(lying, static_cast<int>(tether.deployedParticleCount()) / 2);  // the case: lying on them
  EXPECT_LE(total / 400.0, 2.5);
  EXPECT_EQ(tether.recoveryCount(), 0u) << tether.lastFailure();
}

TEST(MeshObstacle, ACableLaidOutThroughAMeshComesOutWithoutBeingThrown)
{
  // 20 m of heavy cable laid out slack from a spool 4 m over a flat, frictionless mesh to a vehicle 0.3 m
  // over it, 16.4 m away: as laid, its middle hangs 2.8 m through the mesh. The contact pushes it out within
  // its first step. Undoing that overlap (up to 2.8 m) in one 5 ms step would leave the particles hundreds
  // of metres a second of velocity; WorldContact::limitRebound lets a push send a particle off no faster
  // than kMaxRebound. Without it a particle is 20.5 m from the spool at step 2.
  ObstacleSpec m = spec(ShapeType::Mesh);
  m.name = "flat";
  m.file = "(in memory)";
  m.friction = 0.0;
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(std::make_unique<MeshObstacle>(m, flatMesh(40, 1.0)));  // 40 m x 40 m at z = 0
  const TetherParams params = heavyCable(20.0, 0.1);
  const Position spool(0.0, -8.0, 4.0), vehicle(0.5, 8.0, 0.3);
  World world;
  world.setContactBetweenTethers(false);
  ASSERT_TRUE(world.add("tether", std::make_unique<Tether>(params, spool, vehicle)).ok);
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  const Tether& tether = world.tether(0);
  double lowest = 0.0;
  for (std::size_t i = 0; i < tether.deployedParticleCount(); ++i)
  {
    lowest = std::min(lowest, tether.particle(i).z());
  }
  ASSERT_LT(lowest, -2.0);  // the case: laid out well through the mesh
  const double radius = 0.5 * params.diameter;
  for (int k = 1; k <= 400; ++k)
  {
    ASSERT_TRUE(world.advanceTo(0.005 * k).ok);
    for (std::size_t i = 0; i < tether.deployedParticleCount(); ++i)
    {
      // Joined to the spool by 20 m of cable, no particle can be further from it without the cable pulled
      // apart. (The push-out may stretch a segment within a step, which the next solve undoes; the 3.6 m of
      // slack over the 16.4 m between spool and vehicle leaves an intact cable well inside this bound.)
      ASSERT_LE((tether.particle(i) - spool).norm(), params.initial_deployed_length) << "step " << k << ", " << i;
      // Out of the mesh after its first step, and kept out (to what one sub-step of sinking leaves).
      ASSERT_GT(tether.particle(i).z(), 0.5 * radius) << "step " << k << ", " << i;
    }
  }
  EXPECT_EQ(tether.recoveryCount(), 0u);
}

}  // namespace
}  // namespace rov_tether::test
