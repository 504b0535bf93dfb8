#include "rov_tether/geometry/mesh_obstacle.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/collision.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>

namespace rov_tether
{
namespace
{

/// At most this many overlapping triangles are measured per query; a cable segment over a mesh finer than
/// itself touches a few, so this only bounds a pathological query (a segment lying along a fan of slivers).
constexpr std::size_t kMaxTriangles = 64;
/// A capsule whose box spans more cells of the grid than this walks FCL's tree instead.
constexpr long kMaxQueryCells = 27;
/// Cells are at least this fraction of the widest triangle, so no triangle is filed in more than
/// (1 / kWidestFraction + 1)^3 cells.
constexpr double kWidestFraction = 1.0 / 8.0;

/// The point of triangle (a, b, c) closest to p (Ericson 2005, 5.1.5: Voronoi regions of the corners, the
/// edges, the face).
Position closestPointOnTriangle(const Position& p, const Position& a, const Position& b, const Position& c)
{
  const Position ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0)
  {
    return a;
  }
  const Position bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3)
  {
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
  {
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Position cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6)
  {
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
  {
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
  {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

/// Whether x projects onto triangle (a, b, c) of normal n along n (on the inner side of all three edges).
bool overFace(const Position& x, const Position& a, const Position& b, const Position& c, const Position& n)
{
  return n.dot((b - a).cross(x - a)) >= 0.0 && n.dot((c - b).cross(x - b)) >= 0.0 && n.dot((a - c).cross(x - c)) >= 0.0;
}

/// Whether segment [p, q] passes through triangle (a, b, c) of unit normal n (its plane crossed inside it).
bool crossesTriangle(const Position& p, const Position& q, const Position& a, const Position& b, const Position& c,
                     const Position& n)
{
  const double hp = n.dot(p - a), hq = n.dot(q - a);
  if ((hp > 0.0 && hq > 0.0) || (hp < 0.0 && hq < 0.0) || hp == hq)
  {
    return false;
  }
  return overFace(p + (hp / (hp - hq)) * (q - p), a, b, c, n);
}

/**
 * The capsule [p, q] of `radius` against one triangle (a, b, c) with unit front normal n, all in the mesh
 * frame: false when they do not overlap, else where and how deep (see mesh_obstacle.hpp for the way out).
 */
bool pushTriangle(const Position& p, const Position& q, double radius, const Position& a, const Position& b,
                  const Position& c, const Position& n, Push* out)
{
  const double hp = n.dot(p - a), hq = n.dot(q - a);
  // Through the face, or behind it within reach: the deeper end goes back to `radius` in front of it.
  auto from_behind = [&]()
  {
    out->t = hp <= hq ? 0.0 : 1.0;
    out->depth = radius - std::min(hp, hq);
    out->normal = n;
    return true;
  };
  // How far each end is beyond each edge, across it in the face's plane (times the edge's length: the
  // outward normal (c1 - c0) x n is not unit), and whether it is beyond it by more than the radius.
  const Position* corners[3] = {&a, &b, &c};
  double sp[3], sq[3];
  bool p_far[3], q_far[3];
  for (int k = 0; k < 3; ++k)
  {
    const Position& c0 = *corners[k];
    const Position outward = (*corners[(k + 1) % 3] - c0).cross(n);  // counter-clockwise: points out
    const double reach2 = radius * radius * outward.squaredNorm();
    sp[k] = outward.dot(p - c0), sq[k] = outward.dot(q - c0);
    p_far[k] = sp[k] * sp[k] > reach2, q_far[k] = sq[k] * sq[k] > reach2;
    // Both ends beyond one edge by more than the radius: the triangle is behind that plane, out of reach
    // (a neighbour of the triangle a lying cable is over).
    if (sp[k] > 0.0 && sq[k] > 0.0 && p_far[k] && q_far[k])
    {
      return false;
    }
  }
  // An end over the face: inside all three edges.
  const bool p_over = sp[0] <= 0.0 && sp[1] <= 0.0 && sp[2] <= 0.0;
  const bool q_over = sq[0] <= 0.0 && sq[1] <= 0.0 && sq[2] <= 0.0;
  // Both ends in front of the face and over it (a cable lying on the mesh, the common case): the whole
  // segment is over the face (it is convex), where the gap to it is the height, so the lower end is closest.
  if (hp >= 0.0 && hq >= 0.0 && p_over && q_over)
  {
    const double height = std::min(hp, hq);
    if (!(height < radius))
    {
      return false;
    }
    out->t = hp <= hq ? 0.0 : 1.0;
    out->depth = radius - height;
    out->normal = n;
    return true;
  }
  if (crossesTriangle(p, q, a, b, c, n))
  {
    return from_behind();
  }
  // Not crossing: the closest pair has an end of the segment or an edge of the triangle in it. An end over
  // the face is its height from it; an edge both ends are inside of by more than the radius is further.
  double best = std::numeric_limits<double>::infinity(), best_t = 0.0;
  Position best_gap = Position::Zero();
  for (int end = 0; end < 2; ++end)
  {
    const Position& e = end == 0 ? p : q;
    const double h = end == 0 ? hp : hq;
    const Position gap =
        (end == 0 ? p_over : q_over) ? Position(h * n) : Position(e - closestPointOnTriangle(e, a, b, c));
    if (gap.squaredNorm() < best)
    {
      best = gap.squaredNorm(), best_t = end, best_gap = gap;
    }
  }
  for (int k = 0; k < 3; ++k)
  {
    if (sp[k] < 0.0 && sq[k] < 0.0 && p_far[k] && q_far[k])
    {
      continue;
    }
    double s = 0.0, u = 0.0;
    const Position& c0 = *corners[k];
    const Position& c1 = *corners[(k + 1) % 3];
    closestSegmentParameters(p, q, c0, c1, &s, &u);
    const Position gap = (p + s * (q - p)) - (c0 + u * (c1 - c0));
    if (gap.squaredNorm() < best)
    {
      best = gap.squaredNorm(), best_t = s, best_gap = gap;
    }
  }
  const double distance = std::sqrt(best);
  if (!(distance < radius))
  {
    return false;
  }
  if (hp + best_t * (hq - hp) < 0.0)  // the closest point on the axis is behind the plane
  {
    return from_behind();
  }
  out->t = best_t;
  out->depth = radius - distance;
  out->normal = distance > 1e-12 * radius ? Position(best_gap / distance) : n;
  return true;
}

}  // namespace

struct MeshObstacle::Fcl
{
  fcl::BVHModel<fcl::OBBRSSd> model;
  fcl::CollisionRequestd request{kMaxTriangles, false};
  fcl::CollisionResultd result;  ///< Kept so its contact list keeps its capacity.
  std::vector<int> stack;        ///< push's traversal: the nodes still to visit, sized to the tree's depth.
};

namespace
{

/// Files loadTriangleMesh opened (meshFilesRead).
std::atomic<std::size_t> mesh_files_read{0};

}  // namespace

std::size_t meshFilesRead() { return mesh_files_read.load(); }

Status loadTriangleMesh(const std::string& file, double scale, TriangleMesh* mesh)
{
  ++mesh_files_read;
  const std::string who = "mesh file '" + file + "': ";
  if (!std::ifstream(file).good())
  {
    return Status::error(who + "cannot be read (missing, or no permission)");
  }
  Assimp::Importer importer;
  // Polygons to triangles, node transforms into the vertices (DAE scenes), points and lines dropped.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(file, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr)
  {
    return Status::error(who + "not a mesh assimp reads (" + importer.GetErrorString() + ")");
  }
  mesh->vertices.clear();
  mesh->triangles.clear();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
  {
    const aiMesh& part = *scene->mMeshes[m];
    const int base = static_cast<int>(mesh->vertices.size());
    for (unsigned v = 0; v < part.mNumVertices; ++v)
    {
      const aiVector3D& p = part.mVertices[v];
      mesh->vertices.emplace_back(scale * p.x, scale * p.y, scale * p.z);
    }
    for (unsigned f = 0; f < part.mNumFaces; ++f)
    {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices == 3)
      {
        mesh->triangles.emplace_back(base + static_cast<int>(face.mIndices[0]),
                                     base + static_cast<int>(face.mIndices[1]),
                                     base + static_cast<int>(face.mIndices[2]));
      }
    }
  }
  // Triangles of no area have no normal: dropped.
  mesh->triangles.erase(
      std::remove_if(mesh->triangles.begin(), mesh->triangles.end(),
                     [&](const Eigen::Vector3i& t)
                     {
                       const Position& a = mesh->vertices[t[0]];
                       return !((mesh->vertices[t[1]] - a).cross(mesh->vertices[t[2]] - a).norm() > 0.0);
                     }),
      mesh->triangles.end());
  if (mesh->triangles.empty())
  {
    return Status::error(who + "holds no triangle");
  }
  for (const Position& v : mesh->vertices)
  {
    if (!v.allFinite())
    {
      return Status::error(who + "has a vertex that is not a finite number");
    }
  }
  return Status::success();
}

MeshObstacle::MeshObstacle(const ObstacleSpec& spec, TriangleMesh mesh)
    : Obstacle(spec), mesh_(std::move(mesh)), fcl_(std::make_unique<Fcl>())
{
  std::vector<fcl::Vector3d> points(mesh_.vertices.begin(), mesh_.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh_.triangles.size());
  normals_.reserve(mesh_.triangles.size());
  for (const Eigen::Vector3i& t : mesh_.triangles)
  {
    triangles.emplace_back(t[0], t[1], t[2]);
    const Position& a = mesh_.vertices[t[0]];
    normals_.push_back((mesh_.vertices[t[1]] - a).cross(mesh_.vertices[t[2]] - a).normalized());
  }
  for (const Position& v : mesh_.vertices)
  {
    local_bounds_.grow(v);
  }
  fcl_->model.beginModel(static_cast<int>(triangles.size()), static_cast<int>(points.size()));
  fcl_->model.addSubModel(points, triangles);
  fcl_->model.endModel();
  fcl_->request.gjk_solver_type = fcl::GST_INDEP;  // libccd's allocates a triangle per test
  fcl_->result.clear();
  // The depth of FCL's tree bounds push's stack (one pending sibling per level, plus the root).
  std::vector<std::pair<int, int>> pending{{0, 1}};
  int depth = 1;
  while (!pending.empty())
  {
    const auto [node, level] = pending.back();
    pending.pop_back();
    depth = std::max(depth, level);
    const auto& bv = fcl_->model.getBV(node);
    if (!bv.isLeaf())
    {
      pending.emplace_back(bv.leftChild(), level + 1);
      pending.emplace_back(bv.rightChild(), level + 1);
    }
  }
  fcl_->stack.resize(depth + 1);
  fileTriangles();
  placed();
}

void MeshObstacle::fileTriangles()
{
  // Cells as wide as a triangle on average: a cable segment's box then meets a few cells of a few triangles.
  double mean = 0.0, widest = 0.0;
  std::vector<Aabb> boxes(mesh_.triangles.size());
  for (std::size_t k = 0; k < mesh_.triangles.size(); ++k)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      boxes[k].grow(mesh_.vertices[mesh_.triangles[k][corner]]);
    }
    const double extent = (boxes[k].hi - boxes[k].lo).maxCoeff();
    mean += extent / static_cast<double>(mesh_.triangles.size());
    widest = std::max(widest, extent);
  }
  const double cell = std::max({mean, kWidestFraction * widest, 1e-9 * (local_bounds_.hi - local_bounds_.lo).maxCoeff(),
                                std::numeric_limits<double>::min()});
  constexpr long kAll = std::numeric_limits<long>::max();
  std::vector<std::uint32_t> bucket_of;
  std::vector<std::uint32_t> triangle_of;
  for (std::size_t k = 0; k < boxes.size(); ++k)
  {
    boxes[k].inflate(1e-9 * cell);  // a triangle on a cell's face is filed on both sides
  }
  cells_.reset(cell, 4 * boxes.size());
  for (std::size_t k = 0; k < boxes.size(); ++k)
  {
    cells_.forCells(boxes[k], kAll,
                    [&](std::size_t b)
                    {
                      bucket_of.push_back(static_cast<std::uint32_t>(b));
                      triangle_of.push_back(static_cast<std::uint32_t>(k));
                    });
  }
  sortByKey(bucket_of, triangle_of, cells_.buckets(), start_, filed_);
}

MeshObstacle::~MeshObstacle() = default;

void MeshObstacle::placed()
{
  bounds_ = Aabb();
  for (int corner = 0; corner < 8; ++corner)
  {
    bounds_.grow(pose_ * Position((corner & 1) ? local_bounds_.hi.x() : local_bounds_.lo.x(),
                                  (corner & 2) ? local_bounds_.hi.y() : local_bounds_.lo.y(),
                                  (corner & 4) ? local_bounds_.hi.z() : local_bounds_.lo.z()));
  }
}

bool MeshObstacle::push(const Position& a, const Position& b, double radius, Push* out) const
{
  return pushNear(a, b, radius, out, nullptr);
}

bool MeshObstacle::pushNear(const Position& a, const Position& b, double radius, Push* out, Near* near) const
{
  // Into the mesh frame: the grid and the BVH were built there once (and a kept box stays valid as the
  // mesh moves).
  const Eigen::Isometry3d to_local = pose_.inverse(Eigen::Isometry);
  const Position la = to_local * a, lb = to_local * b;
  // The filters below leave the exact test a little slack: a cable resting on the mesh sits at one radius
  // to rounding, and whether it touches decides whether friction holds it.
  const double reach = radius * (1.0 + 1e-9);
  Aabb box;
  box.grow(la), box.grow(lb);
  box.inflate(reach);
  int kept = -1;
  // A triangle that can touch the capsule: within reach of its plane, and its box meeting the capsule's.
  auto measure = [&](std::uint32_t triangle)
  {
    const Eigen::Vector3i& t = mesh_.triangles[triangle];
    const Position& v0 = mesh_.vertices[t[0]];
    const double hp = normals_[triangle].dot(la - v0), hq = normals_[triangle].dot(lb - v0);
    if ((hp > reach && hq > reach) || (hp < -reach && hq < -reach))
    {
      return;
    }
    if (apart(triangle, box))
    {
      return;
    }
    // Measured in any order, to the same answer (keepDeeper breaks ties by number); twice if listed twice.
    keepDeeper(static_cast<int>(triangle), la, lb, radius, &kept, out);
  };
  if (near != nullptr && near->owner != nullptr && near->owner != this)
  {
    near = nullptr;  // kept by another mesh (a segment near two): this one queries its grid each time
  }
  const bool inside = near != nullptr && near->owner == this && near->count != Near::kEmpty &&
                      (near->box.lo.array() <= box.lo.array()).all() && (box.hi.array() <= near->box.hi.array()).all();
  if (!inside && near != nullptr)
  {
    // Keep the triangles near the segment's box grown by a skin of two radii and a tenth of its length, as
    // far as they fit: while the box stays inside, they are all that can touch it.
    near->owner = this;
    near->count = 0;
    near->box = box;
    near->box.inflate(2.0 * radius + 0.1 * (lb - la).norm());
    const Aabb& wide = near->box;
    const bool listed = cells_.forCells(
        wide, kMaxQueryCells,
        [&](std::size_t cell)
        {
          for (std::uint32_t k = start_[cell]; k < start_[cell + 1] && near->count != Near::kTooMany; ++k)
          {
            const std::uint32_t triangle = filed_[k];
            if (apart(triangle, wide) || std::find(near->items.begin(), near->items.begin() + near->count, triangle) !=
                                             near->items.begin() + near->count)
            {
              continue;
            }
            if (near->count == Near::kCapacity)
            {
              near->count = Near::kTooMany;  // queries the grid until the segment leaves the box
              return;
            }
            near->items[static_cast<std::size_t>(near->count++)] = triangle;
          }
        });
    if (!listed)
    {
      near->count = Near::kEmpty;  // a box too wide for the grid: nothing kept
    }
  }
  if (near != nullptr && near->count >= 0)
  {
    for (int k = 0; k < near->count; ++k)
    {
      measure(near->items[static_cast<std::size_t>(k)]);
    }
    return kept >= 0 && toWorld(out);
  }
  const bool small = cells_.forCells(box, kMaxQueryCells,
                                     [&](std::size_t cell)
                                     {
                                       for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k)
                                       {
                                         measure(filed_[k]);
                                       }
                                     });
  if (!small)
  {
    return walkTree(la, lb, radius, out);
  }
  return kept >= 0 && toWorld(out);
}

bool MeshObstacle::pushThroughTree(const Position& a, const Position& b, double radius, Push* out) const
{
  const Eigen::Isometry3d to_local = pose_.inverse(Eigen::Isometry);
  return walkTree(to_local * a, to_local * b, radius, out);
}

bool MeshObstacle::walkTree(const Position& la, const Position& lb, double radius, Push* out) const
{
  // The capsule's box: along the segment, r wider all round.
  fcl::OBBd query;
  const Position axis = lb - la;
  const double length = axis.norm();
  query.axis = length > 0.0 ? Eigen::Quaterniond::FromTwoVectors(Position::UnitZ(), axis).toRotationMatrix()
                            : Eigen::Matrix3d::Identity();
  query.To = 0.5 * (la + lb);
  query.extent = Position(radius, radius, 0.5 * length + radius);
  // Depth first through FCL's tree: a node whose box misses the capsule's is skipped with all below it.
  int* stack = fcl_->stack.data();
  int top = 0;
  stack[top++] = 0;
  int kept = -1;
  while (top > 0)
  {
    const auto& node = fcl_->model.getBV(stack[--top]);
    if (!node.bv.obb.overlap(query))
    {
      continue;
    }
    if (!node.isLeaf())
    {
      stack[top++] = node.rightChild();
      stack[top++] = node.leftChild();
      continue;
    }
    const int triangle = node.primitiveId();
    keepDeeper(triangle, la, lb, radius, &kept, out);
  }
  return kept >= 0 && toWorld(out);
}

bool MeshObstacle::apart(std::uint32_t triangle, const Aabb& box) const
{
  const Eigen::Vector3i& t = mesh_.triangles[triangle];
  const Position &v0 = mesh_.vertices[t[0]], &v1 = mesh_.vertices[t[1]], &v2 = mesh_.vertices[t[2]];
  return (v0.array().max(v1.array()).max(v2.array()) < box.lo.array()).any() ||
         (v0.array().min(v1.array()).min(v2.array()) > box.hi.array()).any();
}

void MeshObstacle::keepDeeper(int triangle, const Position& la, const Position& lb, double radius, int* kept,
                              Push* out) const
{
  const Eigen::Vector3i& t = mesh_.triangles[triangle];
  Push candidate;
  if (!pushTriangle(la, lb, radius, mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]],
                    normals_[triangle], &candidate))
  {
    return;
  }
  // Depths equal to rounding (two triangles meeting at the closest point) go to the lower-numbered
  // triangle, so the answer does not depend on the order the grid or the tree visits them in.
  const double tie = 1e-12 * radius;
  if (*kept < 0 || candidate.depth > out->depth + tie || (candidate.depth >= out->depth - tie && triangle < *kept))
  {
    *out = candidate;
    *kept = triangle;
  }
}

bool MeshObstacle::toWorld(Push* out) const
{
  out->u = 0.0;
  out->normal = pose_.linear() * out->normal;
  return true;
}

bool MeshObstacle::pushThroughFclCollide(const Position& a, const Position& b, double radius, Push* out) const
{
  // Into the mesh frame: the BVH was built there once.
  const Eigen::Isometry3d to_local = pose_.inverse(Eigen::Isometry);
  const Position la = to_local * a, lb = to_local * b;
  const Position axis = lb - la;
  const double length = axis.norm();
  fcl::Transform3d capsule_pose = fcl::Transform3d::Identity();
  capsule_pose.translation() = 0.5 * (la + lb);
  if (length > 0.0)
  {
    capsule_pose.linear() = Eigen::Quaterniond::FromTwoVectors(Position::UnitZ(), axis).toRotationMatrix();
  }
  const fcl::Capsuled capsule(radius, length);
  fcl_->result.clear();
  fcl::collide(&fcl_->model, fcl::Transform3d::Identity(), &capsule, capsule_pose, fcl_->request, fcl_->result);
  const std::size_t found = fcl_->result.numContacts();
  int kept = -1;
  for (std::size_t k = 0; k < found; ++k)
  {
    const fcl::Contactd& contact = fcl_->result.getContact(k);
    const int triangle = contact.o1 == &fcl_->model ? contact.b1 : contact.b2;
    keepDeeper(triangle, la, lb, radius, &kept, out);
  }
  return kept >= 0 && toWorld(out);
}

std::unique_ptr<Obstacle> makeMeshObstacle(const ObstacleSpec& spec, Status* status)
{
  Status check = validate(spec);
  TriangleMesh mesh;
  if (check && spec.type != ShapeType::Mesh)
  {
    check = Status::error("obstacle '" + spec.name + "': is a " + shapeTypeName(spec.type) + ", not a mesh");
  }
  if (check)
  {
    check = loadTriangleMesh(spec.file, spec.scale, &mesh);
    if (!check)
    {
      check.message = "obstacle '" + spec.name + "': " + check.message;
    }
  }
  std::unique_ptr<Obstacle> made;
  if (check)
  {
    made = std::make_unique<MeshObstacle>(spec, std::move(mesh));
  }
  if (status != nullptr)
  {
    *status = check;
  }
  return made;
}

}  // namespace rov_tether

// The module's entry point, loaded by makeObstacle (make_obstacle.cpp) with dlopen: C linkage, so its name
// is known without C++ mangling.
extern "C" __attribute__((visibility("default"))) rov_tether::Obstacle* rov_tether_make_mesh_obstacle(
    const rov_tether::ObstacleSpec* spec, rov_tether::Status* status)
{
  return rov_tether::makeMeshObstacle(*spec, status).release();
}
