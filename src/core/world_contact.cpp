#include "rov_tether/core/world_contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace rov_tether
{

void WorldContact::resize()
{
  const std::size_t n = scene_.cables[self_]->size();
  record_.obstacle.assign(n, -1);
  state_.normal.assign(n, Position::Zero());
  state_.pushed.assign(n, -1.0);
  state_.held.assign(n, 0.0);
  state_.hold.assign(n, 0.0);
  state_.slip.assign(n, Position::Zero());
  state_.mu.assign(n, 0.0);
  state_.touched.clear();
  state_.touched.reserve(n);
  state_.warm.clear();
  state_.warm.reserve(n);
  state_.warm_h = 0.0;
  state_.touching.reserve(n);
  scratch_.deep.reserve(n);
  scratch_.next_deep.reserve(n);
  record_.tether.assign(n, -1);
  record_.point.assign(n, Position::Zero());
  scratch_.candidates.reserve(scene_.obstacles.size());
  std::size_t segments = 0;
  for (const Cable* cable : scene_.cables)
  {
    segments += cable->size();
  }
  scratch_.near.reserve(segments);
  owed_.sent.resize(scene_.cables.size());
  owed_.mark.resize(scene_.cables.size());
  for (std::size_t k = 0; k < scene_.cables.size(); ++k)
  {
    owed_.sent[k].assign(scene_.cables[k]->size(), Position::Zero());
    owed_.mark[k].assign(scene_.cables[k]->size(), 0);
  }
  owed_.list.clear();
  owed_.list.reserve(segments);
  state_.partner.assign(n, Partner{});
  state_.near_obstacle.assign(n, Obstacle::Near{});
  reaction_.resize(scene_.cables.size());
  reaction_[self_].assign(n, Position::Zero());
}

void WorldContact::clearSent()
{
  for (const auto& [k, p] : owed_.list)
  {
    owed_.sent[k][p] = Position::Zero();
    owed_.mark[k][p] = 0;
  }
  owed_.list.clear();
}

void WorldContact::forget()
{
  for (const std::size_t i : state_.touched)
  {
    state_.pushed[i] = -1.0, state_.held[i] = 0.0, state_.hold[i] = 0.0;
  }
  state_.touched.clear();
  state_.warm.clear();
  state_.warm_h = 0.0;
  // What the cable touched belongs to the cable before: read as this one's until its next step, it gave contact
  // angles of joints that touched nothing (a rebuild of the same particle count, a reset, a re-lay).
  record_.clear();
  clearSent();
  if (self_ < reaction_.size())
  {
    std::fill(reaction_[self_].begin(), reaction_[self_].end(), Position::Zero());
  }
}

void WorldContact::react(std::size_t k, std::size_t s, const Push& push, double momentum)
{
  const Cable& other = *scene_.cables[k];
  if (s + 1 >= other.size() || k >= owed_.sent.size() || owed_.sent[k].size() != other.size())
  {
    return;  // the other cable was rebuilt since this one was sized: World resizes before its next step
  }
  // The impulse -momentum / h n, shared by the other segment's ends as the contact point divides it (so
  // the momentum it gives them sums to it), as the change of velocity it makes; a pinned end (a spool
  // outlet, a vehicle) takes its share itself.
  const double shares[2] = {1.0 - push.u, push.u};
  for (int e = 0; e < 2; ++e)
  {
    const std::size_t p = s + static_cast<std::size_t>(e);
    const double move = -shares[e] * momentum / state_.h * other.inv_mass[p];
    if (!(move != 0.0) || !std::isfinite(move))
    {
      continue;  // nothing, or from a solve that diverged (its tether recovers; the other is not harmed)
    }
    if (owed_.mark[k][p] == 0)
    {
      owed_.mark[k][p] = 1;
      owed_.list.emplace_back(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(p));
    }
    owed_.sent[k][p] += move * push.normal;
  }
}

void WorldContact::sendReaction()
{
  // Friction between tethers: what holds a particle back pushes the tether it slides on forwards (a
  // particle that also touched an obstacle or its own cable keeps its friction's reaction to itself).
  const Cable& cable = *scene_.cables[self_];
  for (const std::size_t i : state_.touched)
  {
    const Partner& partner = state_.partner[i];
    if (partner.tether < 0 || !(state_.hold[i] > 0.0) || !(cable.inv_mass_along[i] > 0.0))
    {
      continue;
    }
    std::vector<Position>& other = reaction_[static_cast<std::size_t>(partner.tether)];
    const Cable& other_cable = *scene_.cables[static_cast<std::size_t>(partner.tether)];
    if (partner.segment + 1 >= other.size() || other.size() != other_cable.size())
    {
      continue;
    }
    // The hold moved the particle back by hold along -slip, along the cable (holdLimit sizes it with the
    // mass along it): momentum -hold slip / w_along over the sub-step.
    const Position impulse = state_.hold[i] / (cable.inv_mass_along[i] * state_.h) * state_.slip[i];
    if (!impulse.allFinite())
    {
      continue;
    }
    other[partner.segment] += (1.0 - partner.u) * other_cable.inv_mass[partner.segment] * impulse;
    other[partner.segment + 1] += partner.u * other_cable.inv_mass[partner.segment + 1] * impulse;
  }
  for (const auto& [k, p] : owed_.list)
  {
    if (p < reaction_[k].size())
    {
      reaction_[k][p] += owed_.sent[k][p];
    }
  }
}

void WorldContact::takeReaction(Cable& cable, std::size_t begin, std::size_t end, double h)
{
  state_.h = h;
  if (self_ >= reaction_.size())
  {
    return;
  }
  // A change of velocity v, taken within this sub-step, moves the particle by v h by its end. No faster
  // than kMaxRebound, as this tether's own pushes (limitRebound): the other tether's push out of an overlap
  // it did not make in its step (two tethers laid out through each other) would throw this one too. Then
  // momentum is not conserved: that overlap's is not physical either.
  std::vector<Position>& mine = reaction_[self_];
  for (std::size_t i = begin; i < std::min(end, mine.size()); ++i)
  {
    if (cable.inv_mass[i] > 0.0 && mine[i].allFinite())
    {
      const double speed = mine[i].norm();
      const Position v = speed > kMaxRebound ? Position(mine[i] * (kMaxRebound / speed)) : mine[i];
      cable.x[i] += h * v.x(), cable.y[i] += h * v.y(), cable.z[i] += h * v.z();
    }
  }
  std::fill(mine.begin(), mine.end(), Position::Zero());
}

double WorldContact::resolve(Cable& cable, std::size_t j, const Push& push, double mu)
{
  const std::size_t k = j + 1;
  const double wa = cable.inv_mass[j], wb = cable.inv_mass[k];
  const double ca = 1.0 - push.t, cb = push.t;
  const double denominator = ca * ca * wa + cb * cb * wb;
  if (!(denominator > 0.0))
  {
    return 0.0;  // both ends pinned (the spool outlet and the vehicle): nothing here can move
  }
  double momentum = 0.0;
  // Moving a by ca wa d / D and b by cb wb d / D along n moves the point at t by exactly d. No end moves
  // further than kMaxEndMove d: with one end pinned (the vehicle, the spool outlet) the free end must move
  // d / ca, without bound as the contact nears the pinned end (two vehicles that meet threw their cables
  // hundreds of metres); up to half way from it (ca >= 1/2) that is at most 2 d and stays exact. With
  // equal masses an end moves at most ca / (ca^2 + cb^2) <= 1.21 d, so free segments are always exact.
  // Beyond, what the pinned end holds in the overlap stays, as where both ends are pinned.
  constexpr double kMaxEndMove = 2.0;
  const double moves[2] = {std::min(ca * wa / denominator, kMaxEndMove) * push.depth,
                           std::min(cb * wb / denominator, kMaxEndMove) * push.depth};
  const std::size_t ends[2] = {j, k};
  for (int e = 0; e < 2; ++e)
  {
    const std::size_t i = ends[e];
    if (!(cable.inv_mass[i] > 0.0))
    {
      continue;
    }
    cable.x[i] += moves[e] * push.normal.x(), cable.y[i] += moves[e] * push.normal.y(),
        cable.z[i] += moves[e] * push.normal.z();
    if (state_.pushed[i] < 0.0)
    {
      state_.pushed[i] = 0.0, state_.normal[i] = Position::Zero(), state_.mu[i] = 0.0, state_.partner[i].tether = -1;
      state_.touched.push_back(i);
    }
    state_.pushed[i] += moves[e];
    state_.normal[i] += push.normal;
    state_.mu[i] = std::max(state_.mu[i], mu);
    momentum += moves[e] / cable.inv_mass[i];
  }
  return momentum;
}

double WorldContact::pullInto(const Cable& cable, std::size_t i, const std::vector<double>& stretch, const Position& n)
{
  // The pull of the two segments on particle i over the step, lambda per segment [kg m] (force lambda / h^2).
  Position pull = Position::Zero();
  if (i > cable.first && i - 1 < stretch.size())
  {
    pull += stretch[i - 1] * cable.direction(i, i - 1);
  }
  if (i + 1 < cable.size() && i < stretch.size())
  {
    pull += stretch[i] * cable.direction(i, i + 1);
  }
  return std::max(0.0, -n.dot(pull));
}

double WorldContact::holdLimit(const Cable& cable, std::size_t i, const std::vector<double>& stretch, Position* normal,
                               double* pulled) const
{
  const double length = state_.normal[i].norm();
  if (!(length > 0.0) || !(state_.mu[i] > 0.0))
  {
    *normal = Position::Zero();
    *pulled = 0.0;
    return 0.0;
  }
  *normal = state_.normal[i] / length;
  // A force F held over the step moves the particle by F h^2 w: w along the cable for the slip (which runs
  // along it where it slides; added mass acts across only), so the pull lambda counts as lambda w_along.
  const double along = cable.inv_mass[i] > 0.0 ? cable.inv_mass_along[i] / cable.inv_mass[i] : 1.0;
  const double into = pullInto(cable, i, stretch, *normal) * cable.inv_mass_along[i];
  *pulled = state_.mu[i] * into;
  return state_.mu[i] * std::max(state_.pushed[i] * along, into);
}

void WorldContact::friction(Cable& cable, const std::vector<double>& stretch)
{
  for (const std::size_t i : state_.touched)
  {
    Position n;
    double pulled = 0.0;
    const double limit = holdLimit(cable, i, stretch, &n, &pulled) - state_.held[i];
    const Position moved(cable.x[i] - cable.px[i], cable.y[i] - cable.py[i], cable.z[i] - cable.pz[i]);
    const Position slide = moved - moved.dot(n) * n;
    const double distance = slide.norm();
    if (distance > 0.0 && limit > 0.0)
    {
      const double take = std::min(distance, limit);
      const Position back = -(take / distance) * slide;
      cable.x[i] += back.x(), cable.y[i] += back.y(), cable.z[i] += back.z();
      state_.held[i] += take;
    }
  }
}

void WorldContact::limitRebound(Cable& cable, double h) const
{
  // A push that cancels the particle's own motion into the contact leaves it at rest along n (an impact
  // is inelastic); one that undoes an overlap the sub-step did not make (a cable laid out through an
  // obstacle, a tether pressed in by another) would leave it the overlap over h. Beyond kMaxRebound, the
  // sub-step's start moves out with the particle: the position keeps the push, the velocity does not.
  const double most = kMaxRebound * h;
  for (const std::size_t i : state_.touched)
  {
    const double length = state_.normal[i].norm();
    if (!(length > 0.0) || !(cable.inv_mass[i] > 0.0))
    {
      continue;
    }
    const Position n = state_.normal[i] / length;
    const double off =
        n.x() * (cable.x[i] - cable.px[i]) + n.y() * (cable.y[i] - cable.py[i]) + n.z() * (cable.z[i] - cable.pz[i]);
    if (off > most)
    {
      const double shift = off - most;
      cable.px[i] += shift * n.x(), cable.py[i] += shift * n.y(), cable.pz[i] += shift * n.z();
    }
  }
}

void WorldContact::warmStart(Cable& cable, double h)
{
  // A hold is a force over the step times h^2 w: the same force over a step of another length.
  const double scale = state_.warm_h > 0.0 ? (h / state_.warm_h) * (h / state_.warm_h) : 0.0;
  state_.warm_h = h;
  for (const std::size_t i : state_.touched)
  {
    state_.hold[i] *= scale;
    if (i <= cable.first || i >= cable.size())
    {
      state_.hold[i] = 0.0;  // reeled in onto the drum, or now the outlet
    }
  }
  applyHold(cable);
}

bool WorldContact::updateHold(const Cable& cable, const std::vector<double>& stretch, bool first)
{
  // A change below this does not warrant another solve [m]: what is left is not lost, the next step's
  // first pass starts from it (warmStart). At 1e-3 r a cable resting on the bench's seabed took 3.9 solves
  // a step, at 2e-2 r 1.01 (the capstan and seabed tests hold either way).
  const double settled = 2e-2 * scene_.radius[self_];
  bool changed = false;
  if (first)
  {
    // A particle held in the last step that touches nothing now lets go: solve again without its hold.
    for (const std::size_t i : state_.warm)
    {
      if (state_.pushed[i] < 0.0)
      {
        changed = changed || state_.hold[i] > settled;
        state_.hold[i] = 0.0;
      }
    }
  }
  for (const std::size_t i : state_.touched)
  {
    Position n;
    double pulled = 0.0;
    const double limit = holdLimit(cable, i, stretch, &n, &pulled);
    const Position moved(cable.x[i] - cable.px[i], cable.y[i] - cable.py[i], cable.z[i] - cable.pz[i]);
    const Position slide = moved - moved.dot(n) * n;
    double hold = 0.0;
    if (first && state_.hold[i] > 0.0)
    {
      // Solved with the last step's hold: without it the particle would have slid by about the slide left
      // plus that hold. Friction takes that back whole while it can (sticking), else mu N against it.
      const Position free = slide + state_.hold[i] * state_.slip[i];
      const double distance = free.norm();
      const Position before = state_.hold[i] * state_.slip[i];
      state_.slip[i] = distance > 0.0 ? Position(free / distance) : Position::Zero();
      hold = std::min(distance, limit);
      changed = changed || (hold * state_.slip[i] - before).norm() > settled;
      state_.hold[i] = hold;
      continue;
    }
    if (first)
    {
      // A cable pulled round the contact slides: friction holds back with the mu N of that pull, along the
      // slip of the solve without it. A particle pressed in otherwise (landing, a load) is held by its slip
      // at first. Later passes correct either guess.
      const double distance = slide.norm();
      state_.slip[i] = distance > 0.0 ? Position(slide / distance) : Position::Zero();
      hold = distance > 0.0 ? std::min(limit, std::max(pulled, distance)) : 0.0;
    }
    else
    {
      // Still slipping forwards: hold more; moved backwards: the particle sticks, hold less.
      hold = std::clamp(state_.hold[i] + slide.dot(state_.slip[i]), 0.0, limit);
    }
    changed = changed || std::abs(hold - state_.hold[i]) > settled;
    state_.hold[i] = hold;
  }
  return changed;
}

void WorldContact::applyHold(Cable& cable) const
{
  for (const std::size_t i : state_.touched)
  {
    const Position back = -state_.hold[i] * state_.slip[i];
    cable.x[i] += back.x(), cable.y[i] += back.y(), cable.z[i] += back.z();
  }
}

double WorldContact::contactSegment(Cable& cable, std::size_t j, double r, double widest, bool others, std::size_t gap)
{
  Push push;
  const double deepest = contactObstacles(cable, j, r, &push);
  if (!others)
  {
    return deepest;
  }
  return std::max(deepest, contactCables(cable, j, r, widest, gap, &push));
}

[[gnu::always_inline]] inline double WorldContact::contactObstacles(Cable& cable, std::size_t j, double r, Push* push)
{
  double deepest = 0.0;
  Aabb box;
  box.grow(cable.position(j)), box.grow(cable.position(j + 1));
  box.inflate(r);
  for (const int i : scratch_.candidates)
  {
    const Obstacle& obstacle = *scene_.obstacles[i];
    if (scene_.bounds[i].overlaps(box) &&
        obstacle.pushNear(cable.position(j), cable.position(j + 1), r, push, &state_.near_obstacle[j]))
    {
      resolve(cable, j, *push, obstacle.friction());
      state_.partner[j].tether = state_.partner[j + 1].tether = kNotATether;
      deepest = std::max(deepest, push->depth);
      record_.obstacle[j] = i;
      record_.point[j] = (1.0 - push->t) * cable.position(j) + push->t * cable.position(j + 1);
    }
  }
  return deepest;
}

[[gnu::always_inline]] inline double WorldContact::contactCables(Cable& cable, std::size_t j, double r, double widest,
                                                                 std::size_t gap, Push* out)
{
  double deepest = 0.0;
  Push& push = *out;
  // Where the obstacles left it: its pairs in the grid, or (moved further since it was filed) a query.
  Aabb now;
  now.grow(cable.position(j)), now.grow(cable.position(j + 1));
  const SegmentGrid::Entry* first = nullptr;
  const SegmentGrid::Entry* last = nullptr;
  if (!scene_.grid.pairsOf(self_, j, now, &first, &last))
  {
    now.inflate(r + widest);
    scene_.grid.query(now, scratch_.near);
    // In the pairs' order (by cable and segment), so the contacts are resolved in one order whichever way
    // they were found, and the result does not depend on when the grid was last filed.
    std::sort(scratch_.near.begin(), scratch_.near.end());
    first = scratch_.near.data(), last = scratch_.near.data() + scratch_.near.size();
  }
  for (const SegmentGrid::Entry* pair = first; pair != last; ++pair)
  {
    const SegmentGrid::Entry& e = *pair;
    const bool own = e.cable == self_;
    const std::size_t s = e.segment;
    if (own && static_cast<std::size_t>(std::labs(static_cast<long>(s) - static_cast<long>(j))) <= gap)
    {
      continue;  // neighbours along the cable: joined, not in contact
    }
    const Cable& other = own ? cable : *scene_.cables[e.cable];
    if (s + 1 >= other.size() || s < other.first)
    {
      continue;
    }
    if (!pushCapsule(cable.position(j), cable.position(j + 1), r, other.position(s), other.position(s + 1),
                     scene_.radius[e.cable], &push))
    {
      continue;
    }
    deepest = std::max(deepest, push.depth);
    if (own)
    {
      // Both capsules are this cable's: each moves half the way.
      push.depth *= 0.5;
      Push back = push;
      back.t = push.u;
      back.normal = -push.normal;
      resolve(cable, j, push, scene_.cable_friction[self_]);
      resolve(cable, s, back, scene_.cable_friction[self_]);
      state_.partner[j].tether = state_.partner[j + 1].tether = state_.partner[s].tether =
          state_.partner[s + 1].tether = kNotATether;
      record_.tether[s] = static_cast<int>(self_);
    }
    else
    {
      react(e.cable, s, push, resolve(cable, j, push, scene_.cable_friction[self_]));
      for (const std::size_t i : {j, j + 1})
      {
        if (state_.partner[i].tether != kNotATether)
        {
          state_.partner[i] = {static_cast<int>(e.cable), s, push.u};
        }
      }
    }
    record_.tether[j] = static_cast<int>(e.cable);
    record_.point[j] = (1.0 - push.t) * cable.position(j) + push.t * cable.position(j + 1);
  }
  return deepest;
}

void WorldContact::beginPass(bool first_pass)
{
  if (first_pass)
  {
    record_.clear();
    state_.deepest = 0.0;
    // Last step's particles keep their holds (warmStart applied them) until updateHold sees whether they
    // still touch; no other particle holds anything.
    for (const std::size_t i : state_.touched)
    {
      state_.pushed[i] = -1.0, state_.held[i] = 0.0;
    }
    state_.warm.swap(state_.touched);
    state_.touched.clear();
    return;
  }
  // Another pass of the same step: the particles touched so far keep their holds; their normals and
  // corrections are this pass's.
  for (const std::size_t i : state_.touched)
  {
    state_.pushed[i] = 0.0, state_.normal[i] = Position::Zero();
  }
}

void WorldContact::findCandidates(const Cable& cable, std::size_t lo, std::size_t hi, double r)
{
  Aabb all;
  for (std::size_t i = lo; i <= hi; ++i)
  {
    all.grow(cable.position(i));
  }
  all.inflate(r);
  scratch_.candidates.clear();
  for (std::size_t i = 0; i < scene_.obstacles.size(); ++i)
  {
    if (scene_.bounds[i].overlaps(all))
    {
      scratch_.candidates.push_back(static_cast<int>(i));
    }
  }
}

void WorldContact::sweepSegments(Cable& cable, std::size_t lo, std::size_t hi, bool first_pass)
{
  if (first_pass)
  {
    state_.touching.clear();
  }
  const double r = scene_.radius[self_];
  double widest = 0.0;
  for (const double other : scene_.radius)
  {
    widest = std::max(widest, other);
  }
  const bool others = scene_.between_tethers && !scene_.grid.empty();
  const std::size_t gap = scene_.self_gap[self_];
  // Gauss-Seidel over the contacts: the step's first sweep visits every segment, the next ones only those
  // that overlapped by more than kSettled of the radius in the last sweep and their neighbours (a push can
  // press a segment into another contact: a second layer of cable wound on a pillar presses the first into
  // it), until no segment overlapped by more than that. The friction passes that solve the step again move
  // the cable by no more than friction holds back (a fraction of what the contacts pushed): their first
  // sweep revisits the segments that touched in the step's first, and a segment that comes to touch only
  // then is found by the next step's first sweep.
  for (int sweep = 0; sweep < kContactSweeps; ++sweep)
  {
    double deepest = 0.0;
    const bool every = sweep == 0 && first_pass;
    // After the first sweep only the segments that were deep in the last one, and their neighbours (whose
    // shared particle their push moved): any other was left within kSettled of the radius by the last
    // sweep, and only a push of another segment of its own cable against it (self-contact) can have moved
    // it since; the next step's first sweep finds what that left.
    const std::vector<std::size_t>& list = sweep == 0 ? state_.touching : scratch_.deep;
    const std::size_t count = every ? hi - lo : list.size();
    scratch_.next_deep.clear();
    for (std::size_t n = 0; n < count; ++n)
    {
      const std::size_t j = every ? lo + n : list[n];
      const double depth = contactSegment(cable, j, r, widest, others, gap);
      deepest = std::max(deepest, depth);
      if (every && depth > 0.0)
      {
        state_.touching.push_back(j);
      }
      if (depth > kSettled * r)
      {
        for (std::size_t k = j > lo ? j - 1 : j; k <= j + 1 && k < hi; ++k)
        {
          if (scratch_.next_deep.empty() || scratch_.next_deep.back() < k)
          {
            scratch_.next_deep.push_back(k);
          }
        }
      }
    }
    if (!(deepest > kSettled * r))
    {
      break;
    }
    scratch_.deep.swap(scratch_.next_deep);
  }
}

void WorldContact::project(Cable& cable, std::size_t begin, std::size_t end, const std::vector<double>& stretch,
                           bool first_pass)
{
  beginPass(first_pass);
  // Each pass of the step's contacts owes its own reactions: the last pass's are sent (sendReaction).
  clearSent();
  const std::size_t lo = begin > cable.first ? begin - 1 : cable.first;
  const std::size_t hi = std::min(end, cable.size() - 1);  // segments [lo, hi) touch a free particle
  if (lo >= hi)
  {
    return;
  }
  findCandidates(cable, lo, hi, scene_.radius[self_]);
  sweepSegments(cable, lo, hi, first_pass);
  if (first_pass)
  {
    // How far the solve's tension pulled a touching particle into its contact this sub-step: it grows as
    // h^2 (lambda w), and a pull beyond the clearance drags the cable through a thin obstacle within one
    // solve. Tether::step cuts the next step finer when it is large (an impact's overlap does not count).
    for (const std::size_t i : state_.touched)
    {
      const double length = state_.normal[i].norm();
      if (length > 0.0)
      {
        state_.deepest =
            std::max(state_.deepest, pullInto(cable, i, stretch, state_.normal[i] / length) * cable.inv_mass[i]);
      }
    }
  }
}

}  // namespace rov_tether
