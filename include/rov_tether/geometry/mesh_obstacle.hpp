#pragma once
/**
 * A triangle mesh obstacle (a seabed, a wreck): read from STL, OBJ or DAE through assimp (triangulated,
 * scaled by spec.scale, placed by the spec's pose), queried through FCL 0.7's bounding-volume tree. Part of
 * rov_tether_geometry; the header needs neither library.
 *
 * push: finds the triangles near the capsule in a uniform grid of the mesh's own frame (HashedCells, cells
 * about a triangle wide, built once, so moving the mesh rebuilds nothing), skips those whose plane or box
 * the capsule misses, and measures the rest exactly (segment against triangle, Ericson 2005, 5.1.5 and
 * 5.1.9); the deepest answers. A capsule wider than a few cells (a long segment over a fine mesh) walks FCL's
 * tree instead (BVHModel<OBBRSS>), skipping every node whose OBB misses the capsule's oriented box. The grid
 * answers a cable segment on the 100,000-triangle seabed several times faster than the tree walk, which is
 * itself faster than FCL's own collide query: bench_contact, BM_ContactMeshPush. The way out is the triangle's front
 * side (its winding, counter-clockwise seen from outside): from the cable's axis in front of a triangle, along the
 * shortest gap to it (the face normal over its face, rounded over its edges and corners); through it, or from behind it
 * within reach, the deeper end of the segment goes back to one radius in front of its plane, along its face normal. So
 * a seabed, front up, holds a cable lying on it, and a closed mesh with outward normals pushes a cable out. A cable
 * more than its radius behind every triangle (deep inside a closed mesh) touches none and is not found; contact
 * substeps keep a cable from getting there.
 *
 * Allocation. push allocates nothing: its traversal stack is sized to the tree's depth here, the query box
 * and the result live on the stack. FCL's own capsule-against-mesh collide query (pushThroughFclCollide,
 * kept to measure the choice) does allocate, even with its result kept and reused and the independent GJK
 * solver: 2 operator new calls per query for the capsule's bounding volume (Capsule::getBoundVertices, the
 * RSS fit) and about one more per triangle touched (EPA::initialize); and it runs GJK on every triangle.
 * bench_contact, BM_ContactMeshPush, counts both (allocs_per_query) and times both: docs/benchmarks.md.
 * Both use scratch kept in the obstacle (the stack; FCL's result), so one thread queries an obstacle at a
 * time (World steps its tethers in turn).
 */

#include <memory>
#include <vector>

#include "rov_tether/core/obstacle.hpp"
#include "rov_tether/core/segment_grid.hpp"

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
/// How many times loadTriangleMesh has opened a file in this process, whether or not it held a mesh (the
/// test that a world's description reads each mesh once).
std::size_t meshFilesRead();

class MeshObstacle : public Obstacle
{
 public:
  /// A mesh obstacle of `spec` (its pose, friction, name) with the triangles of `mesh` (not empty).
  MeshObstacle(const ObstacleSpec& spec, TriangleMesh mesh);
  ~MeshObstacle() override;

  Aabb bounds() const override { return bounds_; }
  bool push(const Position& a, const Position& b, double radius, Push* out) const override;
  /// push, measuring only the triangles kept in `near` while the segment's box stays inside the box they
  /// were kept for (the box grown by two radii and a tenth of the segment); refilled from the grid when it
  /// leaves it. Up to Near::kCapacity triangles; more near, and the grid is queried each time.
  bool pushNear(const Position& a, const Position& b, double radius, Push* out, Near* near) const override;
  /// The same answer found through FCL's capsule-against-mesh collide query (GJK on each triangle it reaches,
  /// up to 64 triangles) instead of push's own walk: allocates (see above); for the benchmark and the test
  /// that the two agree.
  bool pushThroughFclCollide(const Position& a, const Position& b, double radius, Push* out) const;
  /// The same answer through FCL's tree alone (what push does for a capsule wider than a few cells): every
  /// triangle whose leaf's OBB meets the capsule's box; allocates nothing; for the benchmark and the test
  /// that the grid and the tree agree.
  bool pushThroughTree(const Position& a, const Position& b, double radius, Push* out) const;
  std::size_t triangleCount() const { return mesh_.triangles.size(); }

 protected:
  void placed() override;

 private:
  /// Whether triangle `triangle`'s box and `box` (mesh frame) are apart.
  bool apart(std::uint32_t triangle, const Aabb& box) const;
  /// pushThroughTree in the mesh frame.
  bool walkTree(const Position& la, const Position& lb, double radius, Push* out) const;
  /// Measures triangle `triangle` against the local capsule [la, lb] and keeps it in `out` (and its index
  /// in `kept`) when it overlaps deeper than what `out` holds (nothing yet while `kept` is -1).
  void keepDeeper(int triangle, const Position& la, const Position& lb, double radius, int* kept, Push* out) const;
  /// Turns the kept push's normal into the world frame; returns true.
  bool toWorld(Push* out) const;
  /// Files each triangle in the cells of cells_ its box touches (counting sort into start_ and filed_).
  void fileTriangles();
  struct Fcl;  ///< The BVH model, push's stack, the kept FCL request and result (mesh_obstacle.cpp).

  TriangleMesh mesh_;
  std::vector<Position> normals_;  ///< Unit front normal of each triangle, mesh frame.
  Aabb local_bounds_;              ///< Of the vertices, mesh frame [m].
  Aabb bounds_;                    ///< World frame: local_bounds_' corners placed [m].
  std::unique_ptr<Fcl> fcl_;
  /// The triangles by cell, mesh frame: cell b's are filed_[start_[b], start_[b + 1]).
  HashedCells cells_;
  std::vector<std::uint32_t> start_, filed_;
};

/// Builds a mesh obstacle from its spec (validated; the file read through loadTriangleMesh), or null with
/// the reason in `status`.
std::unique_ptr<Obstacle> makeMeshObstacle(const ObstacleSpec& spec, Status* status);

}  // namespace rov_tether
