#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/obstacle.hpp"

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
  /// The bucket of the cell that holds point p (finite).
  std::size_t bucketOf(const Position& p) const
  {
    const double inv = 1.0 / cell_;
    return bucket(static_cast<long>(std::floor(p.x() * inv)), static_cast<long>(std::floor(p.y() * inv)),
                  static_cast<long>(std::floor(p.z() * inv)));
  }
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
 * Counting sort: `items` into `out` by their `keys` (each below `count`), each key's in their order, with
 * key k's in out[start[k], start[k + 1]). Allocates only to grow the vectors.
 */
template <typename T>
void sortByKey(const std::vector<std::uint32_t>& keys, const std::vector<T>& items, std::size_t count,
               std::vector<std::uint32_t>& start, std::vector<T>& out)
{
  start.assign(count + 1, 0u);
  for (const std::uint32_t key : keys)
  {
    ++start[key + 1];
  }
  for (std::size_t k = 0; k < count; ++k)
  {
    start[k + 1] += start[k];
  }
  out.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i)
  {
    out[start[keys[i]]++] = items[i];
  }
  // start[k] now holds the end of key k's items: shift back so it holds their start again.
  for (std::size_t k = count; k > 0; --k)
  {
    start[k] = start[k - 1];
  }
  start[0] = 0;
}

/**
 * The broad phase between cable segments: a uniform grid hashed into a fixed table, filled by counting
 * sort, so rebuilding it allocates nothing once it has seen the largest scene. A segment is filed in every
 * cell its bounds (inflated by a margin) touch; a query returns every segment filed in the cells a box
 * touches, each once.
 *
 * It also lists, once per filing, the pairs of segments whose filed bounds overlap (each found in the one
 * cell that holds the corner of their overlap, so once), leaving out segments of one cable closer along it
 * than its `gap`. A segment that has moved less than `moved` from where it was filed finds every segment
 * the query with its box grown by `moved` would in its list (pairsOf); one that moved further queries.
 */
class SegmentGrid
{
 public:
  struct Entry
  {
    std::uint32_t cable;
    std::uint32_t segment;
    /// By cable, then segment: the order contacts are resolved in.
    bool operator<(const Entry& o) const { return cable < o.cable || (cable == o.cable && segment < o.segment); }
  };

  /// Files the deployed segments of every cable, each inflated by `margin` [m], in cells of `cell` [m], and
  /// lists the pairs whose filed bounds overlap, but for segments of cable c within gap[c] of each other
  /// along it. pairsOf answers for a segment within `moved` [m] (at most `margin`) of where it was filed.
  void build(const std::vector<const Cable*>& cables, double cell, double margin, const std::vector<std::size_t>& gap,
             double moved);
  /// The segments filed in the cells `box` touches, each once, into `out` (cleared first; reserve it).
  void query(const Aabb& box, std::vector<Entry>& out) const;
  /// The segments listed with segment `segment` of cable `cable`, now at `now` (its bounds, not inflated),
  /// in [*begin, *end), ordered by cable and segment; false when it was not filed or has moved further than
  /// `moved` from where it was (then query with its box).
  bool pairsOf(std::size_t cable, std::size_t segment, const Aabb& now, const Entry** begin, const Entry** end) const;
  /// Whether cable `cable` still has the segments it was filed with, each within `moved` of where it was
  /// filed (so every pair the lists miss is further apart than its capsules reach).
  bool holds(std::size_t cable, const Cable& now) const;
  bool empty() const { return entries_.empty(); }

 private:
  /// Whether bounds `now` of filed segment i (offset_ order) lie within `moved` of its filed bounds.
  bool within(std::size_t i, const Aabb& now) const;
  /// Lists the pairs (after build has filed every segment).
  void listPairs(const std::vector<std::size_t>& gap);
  HashedCells cells_;
  std::vector<std::uint32_t> start_;  ///< Bucket b's entries are entries_[start_[b], start_[b + 1]).
  std::vector<Entry> entries_;
  std::vector<Entry> staged_;  ///< (entry, bucket) pairs before the counting sort.
  std::vector<std::uint32_t> staged_bucket_;
  mutable std::vector<std::uint32_t> seen_;  ///< Per filed segment: the query that last returned it.
  std::vector<std::uint32_t> offset_;        ///< Per cable: index of its first segment in seen_.
  std::vector<std::size_t> first_;           ///< Per cable: its spool outlet when filed (Cable::first).
  mutable std::uint32_t query_ = 0;
  std::vector<Aabb> filed_;                ///< Per segment (offset_ order): its bounds when filed (empty: not).
  std::vector<std::uint32_t> pair_start_;  ///< Segment i's pairs are pairs_[pair_start_[i], pair_start_[i + 1]).
  std::vector<Entry> pairs_;
  std::vector<std::uint32_t> staged_owner_;  ///< (owner, pair) before the counting sort.
  std::vector<Entry> staged_pair_;
  double margin_ = 0.0;
  double moved_ = 0.0;
};

}  // namespace rov_tether
