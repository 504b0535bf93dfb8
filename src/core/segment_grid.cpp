#include "rov_tether/segment_grid.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether
{
namespace
{
/// Boxes are a segment and its margin, a few cells wide, and cells are at least a segment long; a box
/// thousands of cells wide comes only from a torn cable.
constexpr long kMaxCells = 4096;
}  // namespace

void HashedCells::reset(double cell, std::size_t items)
{
  cell_ = cell;
  std::size_t table = 64;
  while (table < 2 * items)
  {
    table *= 2;
  }
  mask_ = table - 1;
}

void SegmentGrid::build(const std::vector<const Cable*>& cables, double cell, double margin)
{
  std::size_t segments = 0;
  offset_.resize(cables.size());
  for (std::size_t c = 0; c < cables.size(); ++c)
  {
    offset_[c] = static_cast<std::uint32_t>(segments);
    segments += cables[c]->size();
  }
  seen_.assign(segments, 0u);
  query_ = 0;
  cells_.reset(cell, segments);
  const std::size_t table = cells_.buckets();
  staged_.clear();
  staged_bucket_.clear();
  for (std::size_t c = 0; c < cables.size(); ++c)
  {
    const Cable& cable = *cables[c];
    for (std::size_t j = cable.first; j + 1 < cable.size(); ++j)
    {
      Aabb box;
      box.grow(cable.position(j)), box.grow(cable.position(j + 1));
      box.inflate(margin);
      // A diverged or torn cable (re-laid by its tether's next step) files nothing.
      cells_.forCells(box, kMaxCells,
                      [&](std::size_t b)
                      {
                        staged_.push_back({static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(j)});
                        staged_bucket_.push_back(static_cast<std::uint32_t>(b));
                      });
    }
  }
  start_.assign(table + 1, 0u);
  for (const std::uint32_t b : staged_bucket_)
  {
    ++start_[b + 1];
  }
  for (std::size_t b = 0; b < table; ++b)
  {
    start_[b + 1] += start_[b];
  }
  entries_.resize(staged_.size());
  // Each bucket keeps staging order, so the grid (and the contact order) is deterministic.
  for (std::size_t k = 0; k < staged_.size(); ++k)
  {
    entries_[start_[staged_bucket_[k]]++] = staged_[k];
  }
  // start_[b] now holds the end of bucket b: shift back so it holds its start again.
  for (std::size_t b = table; b > 0; --b)
  {
    start_[b] = start_[b - 1];
  }
  start_[0] = 0;
}

void SegmentGrid::query(const Aabb& box, std::vector<Entry>& out) const
{
  out.clear();
  if (entries_.empty() || !box.lo.allFinite() || !box.hi.allFinite())
  {
    return;
  }
  if (++query_ == 0)
  {
    std::fill(seen_.begin(), seen_.end(), 0u);
    query_ = 1;
  }
  cells_.forCells(box, kMaxCells,
                  [&](std::size_t b)
                  {
                    for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k)
                    {
                      const Entry& e = entries_[k];
                      std::uint32_t& mark = seen_[offset_[e.cable] + e.segment];
                      if (mark != query_)
                      {
                        mark = query_;
                        out.push_back(e);
                      }
                    }
                  });
}

}  // namespace rov_tether
