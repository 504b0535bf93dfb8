#pragma once

#include <memory>
#include <vector>

#include "rov_tether/camera/occluder.hpp"
#include "rov_tether/camera/shape_history.hpp"
#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/core/world.hpp"

namespace rov_tether::camera
{

/**
 * What a camera of a live simulation sees: the recent shapes of every tether of a World (a ShapeHistory
 * each, recorded after every physics tick) as tubes of their diameters at any time within the history,
 * and the occluders: the seabed (the highest `seabed_z` any tether has). Obstacles, once the World holds
 * them, join occluders() here as Occluder implementations.
 */
class CameraScene
{
 public:
  /// `world` must outlive the scene. Shapes are kept over `span` [s].
  explicit CameraScene(const World& world, double span = 1.0);

  /// Records every tether's current shape (after the physics advanced).
  void record();
  /// Forgets every shape (the cameras stopped looking).
  void clear();
  /// Shapes of every tether are known over [oldest(), newest()] [s]; empty() before the first record().
  bool empty() const;
  double oldest() const;
  double newest() const;
  /// Every tether at time t [s] as tubes (storage reused). False when t is outside the history.
  bool tubesAt(double t, std::vector<Tube>& tubes);
  const std::vector<const Occluder*>& occluders() const { return occluders_; }

 private:
  void updateSeabed();

  const World& world_;
  double span_;
  std::vector<ShapeHistory> histories_;
  std::vector<std::vector<Position>> shapes_;
  std::unique_ptr<SeabedOccluder> seabed_;
  std::vector<const Occluder*> occluders_;
};

}  // namespace rov_tether::camera
