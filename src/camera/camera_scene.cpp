#include "rov_tether/camera/camera_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether::camera
{

CameraScene::CameraScene(const World& world, double span) : world_(world), span_(span) { updateSeabed(); }

void CameraScene::updateSeabed()
{
  double seabed = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < world_.size(); ++i)
  {
    const double z = world_.tether(i).params().seabed_z;
    seabed = std::isfinite(z) ? std::max(seabed, z) : seabed;
  }
  if (!std::isfinite(seabed))
  {
    seabed_.reset();
  }
  else if (!seabed_ || seabed_->seabedZ() != seabed)
  {
    seabed_ = std::make_unique<SeabedOccluder>(seabed);
  }
  occluders_.clear();
  if (seabed_)
  {
    occluders_.push_back(seabed_.get());
  }
}

void CameraScene::record()
{
  while (histories_.size() < world_.size())
  {
    histories_.emplace_back(span_);
    shapes_.emplace_back();
  }
  for (std::size_t i = 0; i < world_.size(); ++i)
  {
    histories_[i].record(world_.tether(i));
  }
  updateSeabed();
}

void CameraScene::clear()
{
  for (auto& history : histories_)
  {
    history.clear();
  }
}

bool CameraScene::empty() const
{
  return histories_.empty() ||
         std::any_of(histories_.begin(), histories_.end(), [](const ShapeHistory& h) { return h.empty(); });
}

double CameraScene::oldest() const
{
  double t = -std::numeric_limits<double>::infinity();
  for (const auto& h : histories_)
  {
    t = std::max(t, h.oldest());
  }
  return t;
}

double CameraScene::newest() const
{
  double t = std::numeric_limits<double>::infinity();
  for (const auto& h : histories_)
  {
    t = std::min(t, h.newest());
  }
  return t;
}

bool CameraScene::tubesAt(double t, std::vector<Tube>& tubes)
{
  if (empty())
  {
    return false;
  }
  tubes.resize(histories_.size());
  for (std::size_t i = 0; i < histories_.size(); ++i)
  {
    if (!histories_[i].shapeAt(t, shapes_[i]))
    {
      return false;
    }
    tubes[i] = Tube{&shapes_[i], 0.5 * world_.tether(i).params().diameter};
  }
  return true;
}

}  // namespace rov_tether::camera
