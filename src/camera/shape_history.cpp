#include "rov_tether/camera/shape_history.hpp"

#include <algorithm>
#include <cmath>

namespace rov_tether::camera
{

ShapeHistory::ShapeHistory(double span, double min_interval)
    : span_(span),
      min_interval_(min_interval),
      entries_(static_cast<std::size_t>(std::ceil(span / std::max(min_interval, 1e-4))) + 2)
{
}

double ShapeHistory::oldest() const { return at(0).time; }
double ShapeHistory::newest() const { return at(count_ - 1).time; }

void ShapeHistory::record(const Tether& tether)
{
  const double t = tether.time();
  if (count_ > 0 && t < newest())
  {
    clear();
  }
  if (count_ > 0 && t < newest() + min_interval_ - 1e-9)
  {
    return;
  }
  // Drop what is older than the span (but keep one shape at or before newest - span, to interpolate there).
  while (count_ > 1 && at(1).time <= t - span_)
  {
    start_ = (start_ + 1) % entries_.size(), --count_;
  }
  if (count_ == entries_.size())
  {
    start_ = (start_ + 1) % entries_.size(), --count_;
  }
  Entry& e = entries_[(start_ + count_) % entries_.size()];
  ++count_;
  const Cable& cable = tether.state();
  e.time = t;
  e.first = cable.first;
  e.total = cable.size();
  e.xyz.resize(3 * (cable.size() - cable.first));
  for (std::size_t i = cable.first, k = 0; i < cable.size(); ++i, k += 3)
  {
    e.xyz[k] = static_cast<float>(cable.x[i]);
    e.xyz[k + 1] = static_cast<float>(cable.y[i]);
    e.xyz[k + 2] = static_cast<float>(cable.z[i]);
  }
}

Position ShapeHistory::positionOf(const Entry& e, std::size_t index) const
{
  const std::size_t k = 3 * (index < e.first ? 0 : index - e.first);
  return {e.xyz[k], e.xyz[k + 1], e.xyz[k + 2]};
}

bool ShapeHistory::shapeAt(double t, std::vector<Position>& out) const
{
  if (count_ == 0 || !(t >= oldest() - 1e-9) || !(t <= newest() + 1e-9))
  {
    return false;
  }
  std::size_t k = 0;
  while (k + 1 < count_ && at(k + 1).time <= t)
  {
    ++k;
  }
  const Entry& before = at(k);
  const Entry& after = k + 1 < count_ ? at(k + 1) : before;
  const double alpha =
      after.time > before.time ? std::clamp((t - before.time) / (after.time - before.time), 0.0, 1.0) : 0.0;
  // A cable rebuilt in between (another particle count) cannot be interpolated: the nearer shape.
  const Entry& only = alpha < 0.5 ? before : after;
  if (before.total != after.total || alpha == 0.0)
  {
    out.resize(only.xyz.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
    {
      out[i] = positionOf(only, only.first + i);
    }
    return true;
  }
  const std::size_t first = std::min(before.first, after.first);
  out.resize(before.total - first);
  for (std::size_t i = first; i < before.total; ++i)
  {
    out[i - first] = (1.0 - alpha) * positionOf(before, i) + alpha * positionOf(after, i);
  }
  return true;
}

}  // namespace rov_tether::camera
