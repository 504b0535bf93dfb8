#pragma once
// A tether's cable as sections of their own material (issue 22): what each segment of the cable is made of.

#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rov_tether/core/cable.hpp"
#include "rov_tether/core/cable_section.hpp"
#include "rov_tether/core/status.hpp"
#include "rov_tether/core/tether_params.hpp"

namespace rov_tether
{

/// The material of one section: the tether's parameters with the section's properties set.
struct SectionMaterial
{
  double mass_per_length = 0.0;              ///< [kg/m]
  double weight_in_water = 0.0;              ///< [N/m], down positive
  double diameter = 0.0;                     ///< [m]
  double axial_stiffness = 0.0;              ///< EA [N]
  double bending_stiffness = 0.0;            ///< EI [N m^2]
  double axial_damping = 0.0;                ///< BA [N s]
  double normal_drag_coefficient = 0.0;      ///< [-]
  double tangential_drag_coefficient = 0.0;  ///< [-]
  double added_mass_coefficient = 0.0;       ///< [-]

  /// The tether's own material (a section that sets nothing).
  static SectionMaterial of(const TetherParams& params);
  /// Sets these values on `params` (valid: make() checked them there).
  void applyTo(TetherParams* params) const;
  bool operator==(const SectionMaterial& other) const;
};

/**
 * A cable in sections, in material order from the vehicle end (the last section runs to the drum), each a
 * whole number of segments: segments never straddle a section boundary, so every segment is of one material
 * and the mass and stiffness need no splitting. Material stays with the cable through pay-out and reel-in:
 * segment k counted from the vehicle end is always the same material, whatever is deployed.
 */
class CableSections
{
 public:
  /// The per-metre parameters a section may set.
  static const std::vector<std::string>& properties();

  /// No material until make() (which gives a uniform tether its one section).
  CableSections() = default;

  /**
   * Checks `sections` against `params` (resolved: segment_length not `auto`) and builds the cable's material.
   * Refused, with every reason, when: a length is not finite and positive, or missing before the last
   * section; a length is not a whole number of segments (within 1e-6 of one); the lengths do not add up to
   * cable_length; a property is not one of properties(), is set twice in a section, or is out of the range
   * the parameter table gives the tether's own (the same check, named by its section).
   */
  static Status make(const TetherParams& params, const std::vector<CableSection>& sections, CableSections* out);

  /**
   * Fills `cable`'s loading (CableLoading) from params' sections and attachments (params resolved and valid,
   * the cable sized for it): empty when the sections are one material and there are no attachments. An
   * attachment between two particles is split between them in proportion to its distance from each (its force
   * and mass keep their total and their centre along the cable).
   */
  static void load(const TetherParams& params, Cable* cable);

  /// Where an attachment's material is on a cable of `particles` particles: between particle `near` (on the
  /// vehicle side) and `far` (= near - 1, or near when it falls on a particle), `far_share` of the way.
  struct Place
  {
    std::size_t near = 0, far = 0;
    double far_share = 0.0;
  };
  static Place placeOf(const TetherParams& params, std::size_t particles, const CableAttachment& attachment);

  /// Every problem with params' sections and attachments (params resolved, its own fields valid): make()'s, and
  /// for an attachment a missing or repeated name, an arc length outside (0, cable_length], a negative mass,
  /// added mass, drag area or drag coefficient, a buoyancy that is not finite or beyond +-1e7 N; and, with a solver
  /// that fails at full strain (direct, lumped_mass), a section that would carry its EA or more hanging from either
  /// end: the cable's weight below it with its attachments' loads (a float's lift taken off), with water_surface_z
  /// set counting each piece in water or in air (mass g), whichever loads it more.
  static std::vector<std::string> check(const TetherParams& params);

  /// True when every segment is of one material (no sections, or sections that set nothing different).
  bool uniform() const { return materials_.size() <= 1; }
  /// The sections' materials, from the vehicle end.
  const std::vector<SectionMaterial>& materials() const { return materials_; }
  /// Segments from the vehicle end up to the end of each section (the last: the whole cable's).
  const std::vector<std::size_t>& ends() const { return ends_; }
  /// The section segment k (counted from the vehicle end, 0 the vehicle's) is in.
  std::size_t sectionOf(std::size_t k) const;

 private:
  std::vector<SectionMaterial> materials_;
  std::vector<std::size_t> ends_;
};

}  // namespace rov_tether
