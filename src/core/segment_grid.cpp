#include "rov_tether/core/segment_grid.hpp"

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

void SegmentGrid::build(const std::vector<const Cable*>& cables, double cell, double margin,
                        const std::vector<std::size_t>& gap, double moved)
{
  std::size_t segments = 0;
  offset_.resize(cables.size());
  first_.resize(cables.size());
  for (std::size_t c = 0; c < cables.size(); ++c)
  {
    first_[c] = cables[c]->first;
    offset_[c] = static_cast<std::uint32_t>(segments);
    segments += cables[c]->size();
  }
  seen_.assign(segments, 0u);
  query_ = 0;
  filed_.assign(segments, Aabb());
  margin_ = margin;
  moved_ = moved;
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
      const Aabb bounds = box;
      box.inflate(margin);
      // A diverged or torn cable (re-laid by its tether's next step) files nothing.
      if (cells_.forCells(box, kMaxCells,
                          [&](std::size_t b)
                          {
                            staged_.push_back({static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(j)});
                            staged_bucket_.push_back(static_cast<std::uint32_t>(b));
                          }))
      {
        filed_[offset_[c] + j] = bounds;
      }
    }
  }
  // Each bucket keeps staging order, so the grid (and the contact order) is deterministic.
  sortByKey(staged_bucket_, staged_, table, start_, entries_);
  listPairs(gap);
}

void SegmentGrid::listPairs(const std::vector<std::size_t>& gap)
{
  // Each pair of segments filed in one bucket whose filed bounds overlap, where that bucket is the cell of
  // the overlap's lower corner (both are filed there): each pair once, but for a segment filed twice in a
  // bucket (two of its cells hashed alike), removed below.
  staged_owner_.clear();
  staged_pair_.clear();
  const std::size_t table = cells_.buckets();
  for (std::size_t b = 0; b < table; ++b)
  {
    for (std::uint32_t k1 = start_[b]; k1 < start_[b + 1]; ++k1)
    {
      const Entry e1 = entries_[k1];
      const std::uint32_t i1 = offset_[e1.cable] + e1.segment;
      Aabb box1 = filed_[i1];
      box1.inflate(margin_);
      for (std::uint32_t k2 = k1 + 1; k2 < start_[b + 1]; ++k2)
      {
        const Entry e2 = entries_[k2];
        if (e1.cable == e2.cable && static_cast<std::size_t>(std::labs(static_cast<long>(e1.segment) -
                                                                       static_cast<long>(e2.segment))) <= gap[e1.cable])
        {
          continue;  // neighbours along one cable (or the same segment): joined, never in contact
        }
        const std::uint32_t i2 = offset_[e2.cable] + e2.segment;
        Aabb box2 = filed_[i2];
        box2.inflate(margin_);
        if (!box1.overlaps(box2) || cells_.bucketOf(box1.lo.cwiseMax(box2.lo)) != b)
        {
          continue;
        }
        staged_owner_.push_back(i1), staged_pair_.push_back(e2);
        staged_owner_.push_back(i2), staged_pair_.push_back(e1);
      }
    }
  }
  const std::size_t segments = filed_.size();
  sortByKey(staged_owner_, staged_pair_, segments, pair_start_, pairs_);
  // Each segment's list by cable and segment (the order contacts are resolved in: deterministic), once each.
  std::uint32_t write = 0;
  for (std::size_t i = 0; i < segments; ++i)
  {
    const std::uint32_t begin = pair_start_[i], end = pair_start_[i + 1];
    std::sort(pairs_.begin() + begin, pairs_.begin() + end);
    pair_start_[i] = write;
    for (std::uint32_t k = begin; k < end; ++k)
    {
      if (k == begin || pairs_[k - 1] < pairs_[k])
      {
        pairs_[write++] = pairs_[k];
      }
    }
  }
  pair_start_[segments] = write;
  pairs_.resize(write);
}

bool SegmentGrid::pairsOf(std::size_t cable, std::size_t segment, const Aabb& now, const Entry** begin,
                          const Entry** end) const
{
  if (cable >= offset_.size())
  {
    return false;
  }
  const std::size_t i = offset_[cable] + segment;
  const std::size_t stop = cable + 1 < offset_.size() ? offset_[cable + 1] : filed_.size();
  if (i >= stop)
  {
    return false;
  }
  if (!within(i, now))
  {
    return false;
  }
  *begin = pairs_.data() + pair_start_[i];
  *end = pairs_.data() + pair_start_[i + 1];
  return true;
}

bool SegmentGrid::within(std::size_t i, const Aabb& now) const
{
  // A segment filed nowhere has empty bounds: never within.
  const Aabb& filed = filed_[i];
  return (now.lo.array() >= filed.lo.array() - moved_).all() && (now.hi.array() <= filed.hi.array() + moved_).all();
}

bool SegmentGrid::holds(std::size_t cable, const Cable& now) const
{
  const std::size_t stop = cable + 1 < offset_.size() ? offset_[cable + 1] : filed_.size();
  if (cable >= offset_.size() || now.first != first_[cable] || offset_[cable] + now.size() != stop)
  {
    return false;
  }
  for (std::size_t j = now.first; j + 1 < now.size(); ++j)
  {
    Aabb box;
    box.grow(now.position(j)), box.grow(now.position(j + 1));
    if (!within(offset_[cable] + j, box))
    {
      return false;
    }
  }
  return true;
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
