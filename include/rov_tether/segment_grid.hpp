#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "rov_tether/cable.hpp"
#include "rov_tether/obstacle.hpp"

namespace rov_tether
{

/**
 * The cells of a uniform grid of cubes, hashed into a power-of-two table (Teschner et al. 2003), so a
 * scene of any extent needs a table only as large as what is filed in it. SegmentGrid files cable segments
 * in it; MeshObstacle its triangles.
 */
class HashedCells
{
 public:
  /// Cubes of side `cell` [m] in a table of at least twice `items` buckets (and at least 64).
  void reset(double cell, std::size_t items);
  std::size_t buckets() const { return mask_ + 1; }
  /// Calls visit(bucket) for each cell `box` touches, and returns true; when the box spans more than
  /// `most` cells (or is not finite) it visits none and returns false.
  template <typename F>
  bool forCells(const Aabb& box, long most, F&& visit) const
  {
    if (!box.lo.allFinite() || !box.hi.allFinite())
    {
      return false;
    }
    const double inv = 1.0 / cell_;
    const Position lo = (box.lo * inv).array().floor(), hi = (box.hi * inv).array().floor();
    const Position span = hi - lo + Position::Ones();
    if (!(span.maxCoeff() <= static_cast<double>(most)) || span.prod() > static_cast<double>(most))
    {
      return false;
    }
    const long x0 = static_cast<long>(lo.x()), x1 = static_cast<long>(hi.x());
    const long y0 = static_cast<long>(lo.y()), y1 = static_cast<long>(hi.y());
    const long z0 = static_cast<long>(lo.z()), z1 = static_cast<long>(hi.z());
    for (long ix = x0; ix <= x1; ++ix)
    {
      for (long iy = y0; iy <= y1; ++iy)
      {
        for (long iz = z0; iz <= z1; ++iz)
        {
          visit(bucket(ix, iy, iz));
        }
      }
    }
    return true;
  }

 private:
  std::size_t bucket(long ix, long iy, long iz) const
  {
    const std::uint64_t h = (static_cast<std::uint64_t>(ix) * 73856093u) ^
                            (static_cast<std::uint64_t>(iy) * 19349663u) ^ (static_cast<std::uint64_t>(iz) * 83492791u);
    return static_cast<std::size_t>(h) & mask_;
  }
  double cell_ = 1.0;
  std::size_t mask_ = 0;
};

/**
 * The broad phase between cable segments: a uniform grid hashed into a fixed table, filled by counting
 * sort, so rebuilding it allocates nothing once it has seen the largest scene. A segment is filed in every
 * cell its bounds (inflated by a margin) touch; a query returns every segment filed in the cells a box
 * touches, each once.
 */
class SegmentGrid
{
 public:
  struct Entry
  {
    std::uint32_t cable;
    std::uint32_t segment;
  };

  /// Files the deployed segments of every cable, each inflated by `margin` [m], in cells of `cell` [m].
  void build(const std::vector<const Cable*>& cables, double cell, double margin);
  /// The segments filed in the cells `box` touches, each once, into `out` (cleared first; reserve it).
  void query(const Aabb& box, std::vector<Entry>& out) const;
  bool empty() const { return entries_.empty(); }

 private:
  HashedCells cells_;
  std::vector<std::uint32_t> start_;  ///< Bucket b's entries are entries_[start_[b], start_[b + 1]).
  std::vector<Entry> entries_;
  std::vector<Entry> staged_;  ///< (entry, bucket) pairs before the counting sort.
  std::vector<std::uint32_t> staged_bucket_;
  mutable std::vector<std::uint32_t> seen_;  ///< Per filed segment: the query that last returned it.
  std::vector<std::uint32_t> offset_;        ///< Per cable: index of its first segment in seen_.
  mutable std::uint32_t query_ = 0;
};

}  // namespace rov_tether
