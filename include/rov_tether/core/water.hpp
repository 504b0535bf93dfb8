#pragma once

#include <memory>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/current_field.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/// Net weight in water as a displacement over one (sub-)step of h [s]: -w / mu_eff h^2 [m] (z up).
inline double weightDisplacement(const TetherParams& params, double h)
{
  return -params.weight_in_water / params.effectiveMassPerLength() * h * h;
}

/**
 * How the water moves the free particles over one step: the Verlet prediction with the method's drag,
 * relative to the current, and the net weight. One implementation per drag model (makeDrag).
 */
class Drag
{
 public:
  virtual ~Drag() = default;
  /// Moves particles [begin, end) by inertia, drag, current and weight over a step of h ending at t [s];
  /// sets the previous positions to the current ones. Must not allocate.
  virtual void integrate(Cable& cable, std::size_t begin, std::size_t end, double h, double t,
                         const TetherParams& params, const CurrentField& current) const = 0;
};

/// The paper's velocity damping, eq. (6): x' = x + (x - x_prev) D + drift + weight, D = exp(-gamma h),
/// relative to the local water velocity.
class PaperDamping : public Drag
{
 public:
  void integrate(Cable& cable, std::size_t begin, std::size_t end, double h, double t, const TetherParams& params,
                 const CurrentField& current) const override;
};

/// Quadratic Morison drag per particle's share of cable, normal and tangential, relative to the water;
/// explicit but capped so it never more than stops the relative motion (stable at any step).
class MorisonDrag : public Drag
{
 public:
  void integrate(Cable& cable, std::size_t begin, std::size_t end, double h, double t, const TetherParams& params,
                 const CurrentField& current) const override;
};

/// The drag of `model`.
std::unique_ptr<Drag> makeDrag(DragModel model);

}  // namespace rov_tether
