#include "rov_tether/core/world.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rov_tether/core/topology.hpp"

namespace rov_tether
{

Status World::add(const std::string& name, std::unique_ptr<Tether> tether)
{
  if (!tether)
  {
    return Status::error("world: no tether given for '" + name + "'");
  }
  if (name.empty())
  {
    return Status::error("world: a tether needs a name");
  }
  if (find(name) != npos)
  {
    return Status::error("world: there is already a tether called '" + name + "'");
  }
  if (findObstacle(name) != npos)
  {
    return Status::error("world: there is already an obstacle called '" + name + "'");
  }
  tethers_.push_back(Entry{name, std::move(tether)});
  wireContacts();
  return Status::success();
}

std::size_t World::find(const std::string& name) const
{
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    if (tethers_[i].name == name)
    {
      return i;
    }
  }
  return npos;
}

Status World::advanceTo(double t, std::size_t* steps, StepObserver* observer)
{
  if (!std::isfinite(t) || std::abs(t) > Tether::kMaxTime)
  {
    return Status::error("world: advance rejected: target time must be finite and within +-1e10 s");
  }
  std::size_t taken = 0;
  for (;;)
  {
    // The tether whose next step comes first takes it (ties: the first added), as Tether::advanceTo
    // decides whether a step still fits before t.
    std::size_t next = npos;
    for (std::size_t i = 0; i < tethers_.size(); ++i)
    {
      const Tether& candidate = *tethers_[i].tether;
      if (candidate.stepFits(t) && (next == npos || candidate.nextStepTime() < tethers_[next].tether->nextStepTime()))
      {
        next = i;
      }
    }
    if (next == npos)
    {
      break;
    }
    Tether& stepping = *tethers_[next].tether;
    // Once a round (when a tether steps from another time than the last check: the first of the next round,
    // or any after a clock that went back) the scene takes the tethers' live parameters, and the grid is
    // filed again unless every segment is still within its skin of where it was filed. A tether that has
    // moved out of it in its step, or whose cable was rebuilt (new parameters, a reset), has it filed again
    // before the next step.
    if (contact_on_ && (grid_stale_ || stepping.time() != grid_time_ || cableRebuilt()))
    {
      refreshContact(grid_stale_);
      grid_time_ = stepping.time();
      grid_stale_ = false;
    }
    if (observer != nullptr)
    {
      observer->beforeStep(next);  // after the grid, which is every tether's
    }
    if (tethers_[next].carrier != npos)
    {
      placeMountedSpool(next);
    }
    stepping.step();
    if (tethers_[next].carrier != npos)
    {
      loadCarrier(tethers_[next].carrier);
    }
    grid_stale_ = grid_stale_ || (contact_on_ && scene_.between_tethers && !scene_.grid.holds(next, stepping.state()));
    if (observer != nullptr)
    {
      observer->afterStep(next);
    }
    ++taken;
  }
  for (auto& entry : tethers_)
  {
    // No step left to take: records t as each tether's target time. t passed the same check as
    // Tether::advanceTo's above, so this cannot be refused; were it, the caller hears why.
    const Status recorded = entry.tether->advanceTo(t);
    if (!recorded.ok)
    {
      return recorded;
    }
  }
  if (steps != nullptr)
  {
    *steps = taken;
  }
  return Status::success();
}

Status World::mountSpool(std::size_t i, std::size_t carrier, const Eigen::Vector3d& outlet_offset)
{
  if (i >= tethers_.size() || carrier >= tethers_.size())
  {
    return Status::error("world: spool mount rejected: no such tether");
  }
  const std::string who = "world: spool of '" + tethers_[i].name + "' on '" + tethers_[carrier].name + "' rejected: ";
  if (i == carrier)
  {
    return Status::error(who + "a tether cannot carry its own spool");
  }
  if (tethers_[i].carrier != npos)
  {
    return Status::error(who + "it is already on '" + tethers_[tethers_[i].carrier].name + "'");
  }
  if (!tethers_[carrier].tether->vehicleDynamic())
  {
    return Status::error(
        who + "'" + tethers_[carrier].name +
        "' has no dynamic vehicle to carry it (the runner's model: dynamic, the node's vehicle_model: dynamic)");
  }
  for (std::size_t up = tethers_[carrier].carrier; up != npos; up = tethers_[up].carrier)
  {
    if (up == i)
    {
      return Status::error(who + "'" + tethers_[carrier].name + "' rides, through its spool, on '" + tethers_[i].name +
                           "' (a loop)");
    }
  }
  if (!outlet_offset.allFinite() || outlet_offset.norm() > VehicleParams::kMaxOffset)
  {
    std::ostringstream out;
    out << who << "the outlet offset must be finite and within " << VehicleParams::kMaxOffset
        << " m of the body origin";
    return Status::error(out.str());
  }
  tethers_[i].carrier = carrier;
  tethers_[i].outlet_offset = outlet_offset;
  tethers_[i].carrier_starts = tethers_[carrier].tether->vehicleStarts();
  placeMountedSpool(i, true);
  loadCarrier(carrier);
  return Status::success();
}

void World::placeMountedSpool(std::size_t i, bool jump)
{
  Entry& entry = tethers_[i];
  const Tether& carrier = *tethers_[entry.carrier].tether;
  const VehicleBody* body = carrier.vehicleBody();
  if (body == nullptr)
  {
    return;
  }
  const Position outlet = body->position() + body->attitude() * entry.outlet_offset;
  // A vehicle that started again (a reset) did not travel to where it is: the spool jumps with it.
  const bool restarted = carrier.vehicleStarts() != entry.carrier_starts;
  entry.carrier_starts = carrier.vehicleStarts();
  const bool there = entry.tether->particle(0) == outlet;
  // Within limits: the body's attachment point is (Tether refuses to go beyond them), and the offset within
  // kMaxOffset of it; were it refused, the spool would stay where it was.
  (void)entry.tether->setSpoolPosition(outlet, (jump || restarted) && !there);
}

void World::loadCarrier(std::size_t carrier)
{
  Tether& body_tether = *tethers_[carrier].tether;
  const VehicleBody* body = body_tether.vehicleBody();
  if (body == nullptr)
  {
    return;
  }
  Force force = Force::Zero();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const Entry& entry : tethers_)
  {
    if (entry.carrier == carrier)
    {
      const Force pull = entry.tether->spoolForce();
      force += pull;
      moment += (body->attitude() * entry.outlet_offset).cross(pull);
    }
  }
  (void)body_tether.setVehicleLoad(force, moment);  // finite: a tether's forces are (a failure resets it)
}

double World::time() const
{
  double earliest = tethers_.empty() ? 0.0 : tethers_.front().tether->time();
  for (const auto& entry : tethers_)
  {
    earliest = std::min(earliest, entry.tether->time());
  }
  return earliest;
}

}  // namespace rov_tether

namespace rov_tether
{

const char* topologyKindName(TopologyEntry::Kind kind)
{
  switch (kind)
  {
    case TopologyEntry::Kind::WrapTurns:
      return "wrap_turns";
    case TopologyEntry::Kind::ContactAngle:
      return "contact_angle";
    case TopologyEntry::Kind::LinkingNumber:
      return "linking_number";
    case TopologyEntry::Kind::CapstanRatio:
      return "capstan_ratio";
    case TopologyEntry::Kind::WrapAngle:
      return "wrap_angle";
  }
  return "?";
}

Status World::setObstacles(std::vector<std::unique_ptr<Obstacle>> obstacles)
{
  for (std::size_t i = 0; i < obstacles.size(); ++i)
  {
    if (!obstacles[i])
    {
      return Status::error("world: obstacle " + std::to_string(i) + " is missing");
    }
    const std::string& name = obstacles[i]->name();
    if (find(name) != npos)
    {
      return Status::error("world: obstacle '" + name + "' has the name of a tether");
    }
    for (std::size_t k = 0; k < i; ++k)
    {
      if (obstacles[k]->name() == name)
      {
        return Status::error("world: two obstacles are called '" + name + "'");
      }
    }
  }
  scene_.obstacles = std::move(obstacles);
  scene_.bounds.clear();
  for (const auto& obstacle : scene_.obstacles)
  {
    scene_.bounds.push_back(obstacle->bounds());
  }
  wireContacts();
  return Status::success();
}

std::size_t World::findObstacle(const std::string& name) const
{
  for (std::size_t i = 0; i < scene_.obstacles.size(); ++i)
  {
    if (scene_.obstacles[i]->name() == name)
    {
      return i;
    }
  }
  return npos;
}

void World::setObstaclePose(std::size_t i, const Position& position, const Eigen::Quaterniond& orientation)
{
  scene_.obstacles[i]->setPose(position, orientation);
  scene_.bounds[i] = scene_.obstacles[i]->bounds();
}

void World::setContactBetweenTethers(bool on)
{
  scene_.between_tethers = on;
  wireContacts();
}

void World::wireContacts()
{
  contact_on_ = !tethers_.empty() && (!scene_.obstacles.empty() || scene_.between_tethers);
  contacts_.clear();
  scene_.cables.clear();
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    scene_.cables.push_back(&tethers_[i].tether->state());
    contacts_.push_back(std::make_unique<WorldContact>(scene_, i));
  }
  scene_.radius.assign(tethers_.size(), 0.0);
  scene_.cable_friction.assign(tethers_.size(), 0.0);
  scene_.self_gap.assign(tethers_.size(), 1);
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    contacts_[i]->resize();
    tethers_[i].tether->setWorldContact(contact_on_ ? contacts_[i].get() : nullptr);
  }
  if (contact_on_)
  {
    refreshContact(true);
  }
  grid_stale_ = true;  // sized for the new scene: filed again before the next step
}

bool World::cableRebuilt() const
{
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    if (contacts_[i]->record().obstacle.size() != tethers_[i].tether->state().size())
    {
      return true;
    }
  }
  return false;
}

void World::refreshContact(bool file)
{
  double widest = 0.0, longest = 0.0, motion = 0.0;
  bool resized = false, regapped = false;
  for (std::size_t i = 0; i < tethers_.size(); ++i)
  {
    const Tether& tether = *tethers_[i].tether;
    const TetherParams& p = tether.params();
    scene_.radius[i] = 0.5 * p.diameter;
    scene_.cable_friction[i] = p.cable_friction;
    // A cable turns back onto itself over half a turn of about its diameter: segments closer than that
    // along it touch through their joints, not as contacts.
    const std::size_t gap =
        1 + static_cast<std::size_t>(std::ceil(0.5 * 3.14159265358979 * p.diameter / p.segment_length));
    regapped = regapped || gap != scene_.self_gap[i];
    scene_.self_gap[i] = gap;
    widest = std::max(widest, scene_.radius[i]);
    longest = std::max(longest, p.segment_length);
    const Cable& cable = tether.state();
    resized = resized || contacts_[i]->record().obstacle.size() != cable.size();
    motion = std::max(motion, tether.lastMotion());
  }
  if (resized)
  {
    // A cable was rebuilt (a new cable or segment length): every contact sizes what it keeps of it anew.
    for (const auto& contact : contacts_)
    {
      contact->resize();
    }
  }
  if (!scene_.between_tethers)
  {
    return;
  }
  bool holds = !file && !resized && !regapped && widest == grid_widest_ && longest == grid_longest_;
  for (std::size_t i = 0; holds && i < tethers_.size(); ++i)
  {
    holds = scene_.grid.holds(i, tethers_[i].tether->state());
  }
  if (holds)
  {
    return;  // every segment still within its skin of where it was filed: the pairs still hold
  }
  grid_widest_ = widest;
  grid_longest_ = longest;
  // Filed with a margin of the widest radius w plus a skin, two segments whose filed boxes overlap are
  // listed as a pair. While every segment stays within the skin of where it was filed (checked after each
  // step), a segment that has itself moved up to the skin touches none but its pairs: two capsules that
  // touch have boxes within r_a + r_b <= 2w, so their filed boxes were within 2w + 2 skin, twice the
  // margin. One that moved further within its step queries the grid instead. The skin is twice the last
  // step's fastest motion (what a tether moves in a step, as the grid was once filed every round for), and
  // at least kSkin w, so a cable at rest keeps its filing for many rounds.
  const double skin = std::max(2.0 * motion, kSkin * widest);
  // Cells three segments (or margins) long: a cable is a line, so fewer, fuller cells cost less per query
  // than many sparse ones (BM_ContactWorldStep/0: 2.57 ms at 1x, 2.26 at 2x, 2.09 at 3x, 2.18 at 4x).
  scene_.grid.build(scene_.cables, 3.0 * std::max(longest, 2.0 * skin) + 2.0 * widest, widest + skin, scene_.self_gap,
                    skin);
}

void World::topology(std::vector<TopologyEntry>& out) const
{
  out.clear();
  const std::size_t obstacles = scene_.obstacles.size();
  std::vector<double> angle(obstacles + tethers_.size());
  std::vector<Aabb> hull(tethers_.size());
  for (std::size_t t = 0; t < tethers_.size(); ++t)
  {
    const Cable& cable = tethers_[t].tether->state();
    const topology::Polyline curve = topology::deployed(cable);
    for (std::size_t i = 0; i < curve.count; ++i)
    {
      hull[t].grow(curve.at(i));
    }
    for (std::size_t o = 0; o < obstacles; ++o)
    {
      const Obstacle& obstacle = *scene_.obstacles[o];
      if (obstacle.hasAxis())
      {
        out.push_back({t, false, o, TopologyEntry::Kind::WrapTurns,
                       topology::windingTurns(curve, obstacle.axisPoint(), obstacle.axisDirection())});
        out.push_back({t, false, o, TopologyEntry::Kind::WrapAngle,
                       topology::windingAngle(curve, obstacle.axisPoint(), obstacle.axisDirection())});
      }
    }
    // The contact angle: the turn of the tangent at every joint one of whose segments touches the object. A
    // cable rebuilt since its last step has touched nothing yet: its record was cleared (Contact::forget, as every
    // re-lay clears it), and one of another size is not read.
    std::fill(angle.begin(), angle.end(), 0.0);
    const ContactRecord& record = contacts_[t]->record();
    const std::size_t recorded = record.obstacle.size() == cable.size() ? cable.size() : 0;
    for (std::size_t j = cable.first + 1; j + 1 < recorded; ++j)
    {
      const Position before = cable.direction(j - 1, j), after = cable.direction(j, j + 1);
      const double turn = std::atan2(before.cross(after).norm(), before.dot(after));
      int seen[4] = {-1, -1, -1, -1};
      const int touched[4] = {record.obstacle[j - 1], record.obstacle[j],
                              record.tether[j - 1] < 0 ? -1 : static_cast<int>(obstacles) + record.tether[j - 1],
                              record.tether[j] < 0 ? -1 : static_cast<int>(obstacles) + record.tether[j]};
      for (int k = 0; k < 4; ++k)
      {
        if (touched[k] >= 0 && std::find(seen, seen + 4, touched[k]) == seen + 4)
        {
          seen[k] = touched[k];
          angle[static_cast<std::size_t>(touched[k])] += turn;
        }
      }
    }
    for (std::size_t k = 0; k < angle.size(); ++k)
    {
      if (angle[k] > 0.0)
      {
        const bool is_tether = k >= obstacles;
        const std::size_t object = is_tether ? k - obstacles : k;
        const double mu = is_tether ? scene_.cable_friction[t] : scene_.obstacles[k]->friction();
        out.push_back({t, is_tether, object, TopologyEntry::Kind::ContactAngle, angle[k]});
        out.push_back({t, is_tether, object, TopologyEntry::Kind::CapstanRatio, std::exp(mu * angle[k])});
      }
    }
  }
  for (std::size_t a = 0; a < tethers_.size(); ++a)
  {
    for (std::size_t b = a + 1; b < tethers_.size(); ++b)
    {
      // Closed curves in disjoint boxes are unlinked (a closed curve lies in its points' box: the chord too).
      const double link = hull[a].overlaps(hull[b])
                              ? topology::linkingNumber(topology::deployed(tethers_[a].tether->state()),
                                                        topology::deployed(tethers_[b].tether->state()))
                              : 0.0;
      out.push_back({a, true, b, TopologyEntry::Kind::LinkingNumber, link});
    }
  }
}

}  // namespace rov_tether
