#pragma once
/**
 * A triangle mesh obstacle (a seabed, a wreck): read from STL, OBJ or DAE through assimp (triangulated,
 * scaled by spec.scale, placed by the spec's pose), queried through FCL 0.7 (a BVHModel of OBBRSS boxes
 * in the mesh's own frame, so moving it rebuilds nothing). Part of rov_tether_geometry; the header needs
 * neither library.
 *
 * push: FCL finds the triangles the capsule overlaps (a capsule-against-BVH collide query, independent
 * GJK solver, no contact points); each is then measured exactly here (segment against triangle, Ericson
 * 2005, 5.1.5 and 5.1.9) and the deepest one answers. The way out is the triangle's front side (its winding,
 * counter-clockwise seen from outside): from the cable's axis in front of a triangle, along the shortest
 * gap to it (the face normal over its face, rounded over its edges); from behind it or through it, along its
 * face normal. So a seabed, front up, holds a cable lying on it, and a closed mesh with outward normals
 * pushes a cable out. A cable deeper inside a closed mesh than its radius touches no triangle and is not
 * found (substeps keep a cable from getting there).
 *
 * Allocation: none per query once warm. The query's result and request are kept here and reused (FCL
 * keeps a result's contact list capacity across clear()), the capsule is built on the stack, the OBBRSS
 * mesh-against-shape traversal does not copy the model (FCL copies it only for AABB-type BVHs), and the
 * independent GJK solver works in fixed arrays (the libccd one allocates a triangle per test, so it is not
 * used). bench_contact (BM_MeshPush) counts operator new calls per query and reports them. Because of the
 * kept result, push is not thread-safe: one thread queries an obstacle at a time (World steps its
 * tethers in turn).
 */

#include <memory>
#include <vector>

#include "rov_tether/obstacle.hpp"

namespace rov_tether
{

/// Vertices [m] and counter-clockwise triangles (indices into vertices) in a mesh's own frame.
struct TriangleMesh
{
  std::vector<Position> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

/// Reads every triangle of an STL, OBJ or DAE file (assimp: polygons triangulated, node transforms applied,
/// lines and points dropped), scaled by `scale`. Fails with a message naming the file when it is missing,
/// unreadable, not a mesh assimp knows, or holds no triangle.
Status loadTriangleMesh(const std::string& file, double scale, TriangleMesh* mesh);

class MeshObstacle : public Obstacle
{
 public:
  /// A mesh obstacle of `spec` (its pose, friction, name) with the triangles of `mesh` (not empty).
  MeshObstacle(const ObstacleSpec& spec, TriangleMesh mesh);
  ~MeshObstacle() override;

  Aabb bounds() const override { return bounds_; }
  bool push(const Position& a, const Position& b, double radius, Push* out) const override;
  std::size_t triangleCount() const { return mesh_.triangles.size(); }

 protected:
  void placed() override;

 private:
  struct Fcl;  ///< The BVH model and the kept query request and result (mesh_obstacle.cpp).

  TriangleMesh mesh_;
  std::vector<Position> normals_;  ///< Unit front normal of each triangle, mesh frame.
  Aabb local_bounds_;              ///< Of the vertices, mesh frame [m].
  Aabb bounds_;                    ///< World frame: local_bounds_' corners placed [m].
  std::unique_ptr<Fcl> fcl_;
};

/// Builds a mesh obstacle from its spec (validated; the file read through loadTriangleMesh), or null with
/// the reason in `status`.
std::unique_ptr<Obstacle> makeMeshObstacle(const ObstacleSpec& spec, Status* status);

}  // namespace rov_tether
