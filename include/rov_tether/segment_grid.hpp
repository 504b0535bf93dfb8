#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "rov_tether/cable.hpp"
#include "rov_tether/obstacle.hpp"

namespace rov_tether
{

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
  std::size_t bucket(long ix, long iy, long iz) const;
  template <typename F>
  void forCells(const Aabb& box, F&& visit) const;

  double cell_ = 1.0;
  std::size_t mask_ = 0;
  std::vector<std::uint32_t> start_;  ///< Bucket b's entries are entries_[start_[b], start_[b + 1]).
  std::vector<Entry> entries_;
  std::vector<Entry> staged_;  ///< (entry, bucket) pairs before the counting sort.
  std::vector<std::uint32_t> staged_bucket_;
  mutable std::vector<std::uint32_t> seen_;  ///< Per filed segment: the query that last returned it.
  std::vector<std::uint32_t> offset_;        ///< Per cable: index of its first segment in seen_.
  mutable std::uint32_t query_ = 0;
};

}  // namespace rov_tether
