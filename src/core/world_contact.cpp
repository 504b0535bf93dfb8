#include "rov_tether/world_contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rov_tether
{

void WorldContact::resize()
{
  const std::size_t n = scene_.cables[self_]->size();
  record_.obstacle.assign(n, -1);
  record_.tether.assign(n, -1);
  record_.point.assign(n, Position::Zero());
  candidates_.reserve(scene_.obstacles.size());
  std::size_t segments = 0;
  for (const Cable* cable : scene_.cables)
  {
    segments += cable->size();
  }
  near_.reserve(segments);
}

void WorldContact::resolve(Cable& cable, std::size_t j, const Push& push, double mu) const
{
  const std::size_t k = j + 1;
  const double wa = cable.inv_mass[j], wb = cable.inv_mass[k];
  const double ca = 1.0 - push.t, cb = push.t;
  const double denominator = ca * ca * wa + cb * cb * wb;
  if (!(denominator > 0.0))
  {
    return;  // both ends pinned (the spool outlet and the vehicle): nothing here can move
  }
  // Moving a by ca wa v / D and b by cb wb v / D moves the point at t by exactly v.
  auto move = [&](const Position& v) {
    const Position va = (ca * wa / denominator) * v, vb = (cb * wb / denominator) * v;
    cable.x[j] += va.x(), cable.y[j] += va.y(), cable.z[j] += va.z();
    cable.x[k] += vb.x(), cable.y[k] += vb.y(), cable.z[k] += vb.z();
  };
  move(push.depth * push.normal);
  if (!(mu > 0.0))
  {
    return;
  }
  const Position now = ca * cable.position(j) + cb * cable.position(k);
  const Position before = ca * Position(cable.px[j], cable.py[j], cable.pz[j]) + cb * Position(cable.px[k], cable.py[k], cable.pz[k]);
  const Position moved = now - before;
  const Position slide = moved - moved.dot(push.normal) * push.normal;
  const double length = slide.norm();
  const double limit = mu * push.depth;
  if (length > 0.0)
  {
    move(-(length > limit ? limit / length : 1.0) * slide);
  }
}

void WorldContact::project(Cable& cable, std::size_t begin, std::size_t end) const
{
  record_.clear();
  const std::size_t lo = begin > cable.first ? begin - 1 : cable.first;
  const std::size_t hi = std::min(end, cable.size() - 1);  // segments [lo, hi) touch a free particle
  if (lo >= hi)
  {
    return;
  }
  const double r = scene_.radius[self_];
  Aabb all;
  for (std::size_t i = lo; i <= hi; ++i)
  {
    all.grow(cable.position(i));
  }
  all.inflate(r);
  candidates_.clear();
  for (std::size_t i = 0; i < scene_.obstacles.size(); ++i)
  {
    if (scene_.bounds[i].overlaps(all))
    {
      candidates_.push_back(static_cast<int>(i));
    }
  }
  double widest = 0.0;
  for (const double other : scene_.radius)
  {
    widest = std::max(widest, other);
  }
  const bool others = scene_.between_tethers && !scene_.grid.empty();
  const std::size_t gap = scene_.self_gap[self_];
  Push push;
  for (std::size_t j = lo; j < hi; ++j)
  {
    Aabb box;
    box.grow(cable.position(j)), box.grow(cable.position(j + 1));
    box.inflate(r);
    for (const int i : candidates_)
    {
      const Obstacle& obstacle = *scene_.obstacles[i];
      if (scene_.bounds[i].overlaps(box) && obstacle.push(cable.position(j), cable.position(j + 1), r, &push))
      {
        resolve(cable, j, push, obstacle.friction());
        record_.obstacle[j] = i;
        record_.point[j] = (1.0 - push.t) * cable.position(j) + push.t * cable.position(j + 1);
      }
    }
    if (!others)
    {
      continue;
    }
    box.inflate(widest);
    scene_.grid.query(box, near_);
    for (const SegmentGrid::Entry& e : near_)
    {
      const bool own = e.cable == self_;
      if (own && static_cast<std::size_t>(std::labs(static_cast<long>(e.segment) - static_cast<long>(j))) <= gap)
      {
        continue;  // neighbours along the cable: joined, not in contact
      }
      const Cable& other = own ? cable : *scene_.cables[e.cable];
      const std::size_t s = e.segment;
      if (s + 1 >= other.size())
      {
        continue;
      }
      if (pushCapsule(cable.position(j), cable.position(j + 1), r, other.position(s), other.position(s + 1),
                      scene_.radius[e.cable], &push))
      {
        resolve(cable, j, push, scene_.cable_friction[self_]);
        record_.tether[j] = static_cast<int>(e.cable);
        record_.point[j] = (1.0 - push.t) * cable.position(j) + push.t * cable.position(j + 1);
      }
    }
  }
}

}  // namespace rov_tether
