#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rov_tether/core/cable_section.hpp"
#include "rov_tether/core/line_mass.hpp"

namespace rov_tether
{

/// Constraint solver used for the distance and bending constraints.
enum class SolverType
{
  kPbd,            ///< The paper's Figure 2 projected in a red-black (vectorisable) order.
  kPbdSequential,  ///< The paper's Figure 2 in its literal sequential order (reference, slower).
  kXpbd,           ///< Extended PBD: compliance from axial_stiffness and bending_stiffness, tension in newtons
                   ///< that does not depend on the iteration count or the step.
  kLumpedMass,     ///< Force-based chain: springs of stiffness EA / rest, explicit Verlet; stable only below
                   ///< its critical step (criticalStep()); a blow-up is detected and reported.
  kDirect          ///< Newton on all constraints with an exact (tridiagonal or banded) solve: the length and
                   ///< tension are exact to solver_tolerance at any length; EI bending; no compression.
};

/// Whether `solver` takes a segment at 100% strain (kDivergenceLimit) for a blow-up and re-lays the cable (direct,
/// lumped_mass), so that a load of EA or more (a cable's own weight, an attachment's) is refused with it. pbd and
/// xpbd project the lengths and report no blow-up: with them EA only scales the strain a tension reads as.
inline bool failsAtFullStrain(SolverType solver)
{
  return solver == SolverType::kDirect || solver == SolverType::kLumpedMass;
}

/// How the water resists the cable's motion.
enum class DragModel
{
  kDamping,  ///< The paper's velocity damping (`drag`), relative to the water.
  kMorison   ///< Quadratic Morison drag per segment, separate normal and tangential coefficients, added mass.
};

/// How the spool pays cable out or reels it in (winch.hpp).
enum class WinchMode
{
  kBrake,            ///< A drum held by a brake that slips at brake_tension; never reels in.
  kConstantTension,  ///< An auto-tension winch: pays out above, reels in below target_tension.
  kSpeed,            ///< Pay out (positive) or reel in (negative) at winch_speed, or to a target length.
  kLocked,           ///< The deployed length never changes.
  kStrain            ///< The paper's rule: pay out when the first segment's strain passes payout_threshold.
};

/// The step at which the paper's per-frame parameters (drag, noise) keep their literal meaning [s].
/// 0.02 s is the step of the paper's 2D notebook and the default sub-step of the Unreal Engine cable
/// component the paper modified.
constexpr double kReferenceStep = 0.02;
/// The largest random displacement of a sub-step, as a fraction of segment_length (TetherParams::validate).
constexpr double kMaxNoisePerSegment = 0.1;

/**
 * All model parameters, in SI units, with their defaults.
 *
 * Names are the user interface: the same names are used in `config/default.yaml`, in scenario files
 * and (later) in dynamic_reconfigure. `validate()` names each bad field, its value and its range.
 */
/// `iterations: auto` for `direct`: the most Newton iterations a sub-step may take (it stops on
/// solver_tolerance, in 1-5 on every reference case).
constexpr int kDirectIterations = 10;

struct TetherParams
{
  /// Total length of cable, all of it on the spool at most [m].
  double cable_length = 10.0;
  /// Rest length of one segment [m]; the first (spool-side) segment varies between 0.5x and 1.5x this.
  double segment_length = 0.1;
  /// `segment_length: auto`: segment_length is chosen by resolved() from shape_tolerance and
  /// min_bend_radius (chord error dL^2 / (8 R) <= shape_tolerance).
  bool segment_length_auto = false;
  /// Largest chord (sagitta) error of one segment on the scene's tightest curve, for `auto` [m].
  double shape_tolerance = 0.01;
  /// Tightest radius of curvature the scene is expected to have, for `auto` [m] (a catenary: H / w).
  double min_bend_radius = 1.0;
  /// Deployed length at start [m].
  double initial_deployed_length = 2.0;
  /// Internal fixed step [s].
  double time_step = 0.005;
  /// Constraint solver.
  SolverType solver = SolverType::kDirect;
  /// Sub-steps per time_step [-]: each integrates and solves over time_step / substeps.
  int substeps = 1;
  /// Constraint solver sweeps per sub-step [-].
  int iterations = 10;
  /// pbd: successive over-relaxation factor of each correction [-]; 1 = the paper's projection.
  double over_relaxation = 1.0;
  /// direct: Newton stops when every constraint residual is below this times its segment length [-]
  /// (`iterations` is then the most it may take).
  double solver_tolerance = 1e-8;
  /// `iterations: auto`: resolved() chooses the effort from stretch_tolerance (pbd, xpbd: iterations; lumped_mass:
  /// substeps below half the critical step).
  bool iterations_auto = false;
  /// Mean residual stretch of a hanging cable `iterations: auto` aims for [-].
  double stretch_tolerance = 0.01;
  /// Enable the paper's (i, i+2) bending constraints.
  bool bending = true;
  /// Fraction of velocity kept per reference step (kReferenceStep) [-], (0, 1]. 1 = no damping.
  /// Internally a rate gamma = -ln(drag) / kReferenceStep [1/s], applied as exp(-gamma dt) per step.
  double drag = 0.9;
  /// Random micro-current displacement: half-width of the uniform displacement per axis added to each
  /// free particle per reference step [m]. Scaled by (dt / kReferenceStep)^1.5 at other steps so that the
  /// long-term random walk does not depend on the step.
  double noise = 0.0005;
  /// Seed of the random displacements; the same seed gives the same run.
  std::int64_t seed = 1;
  /// Net weight in water per metre [N/m]; positive sinks, negative floats, 0 = neutrally buoyant.
  double weight_in_water = 0.0;
  /// Mass per metre of cable [kg/m]; converts weight to acceleration and corrections to tension.
  double mass_per_length = 0.1;
  /// Axial stiffness EA [N]. xpbd, lumped_mass and direct use it; pbd does not (docs/model.md), for it it
  /// is only the scale of the equivalent strain T / EA reported beside the geometric strain.
  double axial_stiffness = 1.0e5;
  /// Axial damping BA [N s] (Kelvin-Voigt: a taut segment's tension is EA e + BA de/dt, e its strain; MoorDyn's
  /// BA, OrcaFlex's axial damping), inside `direct`'s and `xpbd`'s implicit steps and on `lumped_mass`'s
  /// explicit one (which it makes shorter: criticalStep()); 0 = none. The spool segment (its rest length the
  /// winch's) is left undamped.
  double axial_damping = 0.0;
  /// Bending stiffness EI [N m^2] of xpbd's and direct's bending at the joints (when `bending` is on); 0 = no
  /// bending resistance. The default is a 2 cm polyurethane-jacketed tether's (E 25 MPa, I = pi d^4 / 64):
  /// without it direct's one-sided segments let the paper's noise crumple a slack cable. pbd's bending
  /// constraints are the paper's, rigid; lumped_mass has no bending.
  double bending_stiffness = 0.2;
  /// Drag model.
  DragModel drag_model = DragModel::kDamping;
  /// Outer diameter of the cable [m] (Morison drag and added mass).
  double diameter = 0.02;
  /// Density of the water [kg/m^3].
  double water_density = 1025.0;
  /// Morison drag coefficient for flow normal to the cable [-].
  double normal_drag_coefficient = 1.2;
  /// Morison (skin friction) coefficient for flow along the cable, on the wetted area pi d [-].
  double tangential_drag_coefficient = 0.008;
  /// Added mass coefficient, applied to the displaced water rho pi d^2 / 4 per metre (morison only) [-].
  double added_mass_coefficient = 1.0;
  /// Uniform water current, world frame [m/s].
  std::array<double, 3> current = {0.0, 0.0, 0.0};
  /// Amplitude of the slow, spatially correlated variation of the current [m/s]; 0 = uniform.
  double current_variation = 0.0;
  /// Height of a flat seabed [m]; NaN (absent) = no seabed.
  double seabed_z = std::numeric_limits<double>::quiet_NaN();
  /// Height of the water surface [m]; NaN (absent) = everything submerged. Above it the cable weighs
  /// mass_per_length g and has no drag or added mass; a segment crossing it is split in proportion.
  double water_surface_z = std::numeric_limits<double>::quiet_NaN();
  /// Coulomb friction coefficient of the seabed [-].
  double seabed_friction = 0.5;
  /// Coulomb friction coefficient of the cable on another cable or on itself (World contact) [-].
  double cable_friction = 0.3;
  /// Winch mode.
  WinchMode winch_mode = WinchMode::kBrake;
  /// `brake`: the spool-end tension at which the brake slips [N].
  double brake_tension = 5.0;
  /// `brake`: the drum's equivalent mass at its radius [kg]; 0 = a massless drum.
  double winch_inertia = 0.0;
  /// `constant_tension`: the spool-end tension the winch holds [N].
  double target_tension = 5.0;
  /// `constant_tension`: no pay-out or reel-in while the tension is within this of the target [N].
  double tension_deadband = 1.0;
  /// Commanded winch speed in `speed` mode [m/s], positive pays out.
  double winch_speed = 0.0;
  /// Largest winch speed in any mode [m/s].
  double max_winch_speed = 1.0;
  /// Largest winch acceleration of `speed` and `constant_tension` [m/s^2].
  double max_winch_acceleration = 1.0;
  /// The winch motor's stall pull [N] (`speed`, `constant_tension`): no reel-in pulls harder; there the drum
  /// stops reeling in and, pulled harder, pays out. 0 = derived, winchPull().
  double max_winch_pull = 0.0;
  /// `strain`: strain of the first free segment beyond which the paper's winch pays out [-].
  double payout_threshold = 0.1;
  /// `strain`: the paper's winch reels in while the deployed length exceeds (1 + reel_in_slack) times the
  /// straight spool-to-vehicle distance [-].
  double reel_in_slack = 0.2;
  /// Deployed length never goes below this [m].
  double min_deployed_length = 0.5;
  /// A vehicle sample further than max_vehicle_speed * dt + max_vehicle_jump from the previous one (dt after it)
  /// is a jump (re-lays the cable) [m].
  double max_vehicle_jump = 1.0;
  /// The fastest the vehicle can move [m/s]: between samples dt apart it may move this * dt more than
  /// max_vehicle_jump without being a jump.
  double max_vehicle_speed = 3.0;

  /// The cable in sections of their own material, from the vehicle end (issue 22); none: one uniform cable of
  /// the parameters above. Not in the parameter table: a list of maps (`sections:` in a description).
  std::vector<CableSection> sections;
  /// Floats and clump weights clipped onto the cable (`attachments:` in a description).
  std::vector<CableAttachment> attachments;

  /// Returns one message per invalid field ("field = value: allowed range"); empty when valid.
  std::vector<std::string> validate() const;
  /// validate() of one section's material (CableSections::make: the tether's parameters with a section's
  /// properties set, its sections and attachments cleared): every check but those of the whole cable, its own weight
  /// against its axial stiffness, which CableSections::check makes section by section.
  std::vector<std::string> validateMaterial() const;

  /// Damping rate gamma [1/s] equivalent to `drag` at kReferenceStep.
  double dampingRate() const;
  /// Velocity factor D kept over one step of length dt [s]: exp(-gamma dt).
  double dampingFactor(double dt) const;
  /// Half-width of the uniform random displacement per axis for one step of length dt [m].
  double noiseAmplitude(double dt) const;
  /// Number of segments the full cable is split into.
  std::size_t segmentCount() const;
  /// Mass per metre including added mass (morison only) [kg/m]: the mass across the cable.
  double effectiveMassPerLength() const;
  /// Mass per metre along the cable (mass_per_length) and across it (effectiveMassPerLength()) [kg/m].
  LineMass lineMass() const { return {mass_per_length, effectiveMassPerLength()}; }
  /// Sub-step length time_step / substeps [s].
  double subStep() const { return time_step / substeps; }
  /// The winch motor's stall pull [N]: max_winch_pull, or when 0, 1.25 x the larger of target_tension +
  /// tension_deadband and brake_tension (a motor a quarter stronger than the tension it is set to hold).
  double winchPull() const;
  /// The largest value of the section parameter `name` along the cable: `own` (the tether's value of it) without
  /// sections, else the largest a section sets or, setting none, has from the tether. Allocates nothing (read every
  /// step).
  double largestOverSections(std::string_view name, double own) const;
  /// The largest EI of the cable [N m^2] (largestOverSections). SolverSettings::from switches bending on by it;
  /// direct reads each segment's own.
  double largestBendingStiffness() const { return largestOverSections("bending_stiffness", bending_stiffness); }
  /// EI bending acts (xpbd's and direct's joints; under direct the cable is a rod, which carries compression):
  /// `bending` on and some EI > 0 (largestBendingStiffness()).
  bool elasticBending() const { return bending && largestBendingStiffness() > 0.0; }
  /// Largest stable sub-step of the explicit lumped_mass chain, dL / sqrt(EA / mu_eff) [s], times
  /// sqrt(1 + zeta^2) - zeta with axial damping (zeta = BA / (dL sqrt(EA mu)), its fastest mode's ratio).
  double criticalStep() const;
  /// A copy with `auto` segment_length and iterations replaced by the chosen values (flags cleared).
  TetherParams resolved() const;
};

/// True when the two parameter sets describe the same particle arrays (cable_length and segment_length):
/// a change of anything else needs no rebuild.
bool sameStructure(const TetherParams& a, const TetherParams& b);

/// A parameter value from any source (YAML, parameter server, command line).
using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::vector<double>>;

/**
 * One row of the parameter table, the single source of every parameter's name, type, unit, default, range
 * and meaning. validate() takes each field's range from it; `cfg/Tether.cfg` (dynamic_reconfigure),
 * `config/default.yaml` and the README's parameter table are generated from it
 * (scripts/generate_parameters.py), and `ParamTable.*` tests fail when a committed one differs.
 */
struct ParameterInfo
{
  std::string name;
  std::string type;  ///< As documented: "double", "int", "bool", "string", "double[3]", "double or auto", ...
  std::string unit;  ///< "-" when dimensionless.
  double min;        ///< Range of the value (each component of a vector) [unit]; NaN: none (bool, string).
  double max;
  bool min_open;  ///< The bound itself is excluded.
  bool max_open;
  std::string range;    ///< How the README states the range when it is not [min, max] (relations, choices).
  std::string meaning;  ///< One line for the README.
  bool live;            ///< Tunable while running (dynamic_reconfigure, cfg/Tether.cfg).
};

/// The parameter table, in documentation order.
const std::vector<ParameterInfo>& parameterInfo();

/// One choice of a string parameter and what it means.
struct ParameterChoice
{
  std::string value;
  std::string meaning;
};

/// The choices of a string parameter (solver, drag_model, winch_mode) in documentation order; empty for
/// any other parameter. The README's range column and the .cfg's enums are made from them.
const std::vector<ParameterChoice>& parameterChoices(const std::string& name);

/// The README's parameter table (header and one row per parameter), generated from parameterInfo() and
/// the defaults of TetherParams.
std::string parameterTableMarkdown();

/// config/default.yaml as generated from parameterInfo() and the defaults: every parameter at its default,
/// each line commented with its unit and meaning (parameter_files.cpp).
std::string defaultYaml();

/// cfg/Tether.cfg as generated from parameterInfo(), parameterChoices() and the defaults: the live
/// parameters, without ranges (parameter_files.cpp).
std::string dynamicReconfigureCfg();

/// A value as the README and default.yaml write it (numbers in %g, lists in brackets, NaN as .nan).
std::string formatParamValue(const ParamValue& value);

/// Names of all parameters, in documentation order.
const std::vector<std::string>& parameterNames();

/// The candidate nearest to `name` by edit distance (insertions, deletions, substitutions), for a "did you
/// mean" after a typo: "" unless it is within 2 edits (1 for names under 6 characters) and nearer than
/// any other.
std::string closestName(const std::string& name, const std::vector<std::string>& candidates);

/// Sets one parameter by name with type checking (integers are accepted for doubles).
/// Returns an empty string on success, otherwise a message naming the parameter. Range checks are
/// left to TetherParams::validate() so that contradictions between fields are reported together.
std::string setParameter(TetherParams& params, const std::string& name, const ParamValue& value);

/// The one loader of parameter values, whatever they came from (scenario and parameter files, the
/// parameter server, the runner's --set, the tests): sets each (name, value) with setParameter, then
/// validates the whole. Returns every problem, each naming its parameter; `params` is changed only when
/// there is none.
std::vector<std::string> applyParameters(const std::vector<std::pair<std::string, ParamValue>>& values,
                                         TetherParams* params);

/// Reads one parameter by name. Throws std::out_of_range for an unknown name.
ParamValue getParameter(const TetherParams& params, const std::string& name);

std::string toString(SolverType solver);
std::string toString(WinchMode mode);
std::string toString(DragModel model);
/// Parses a solver name; returns false for an unknown name.
bool parseSolver(const std::string& text, SolverType* solver);
/// Parses a winch mode name; returns false for an unknown name. `passive`, the old name of `strain`, is
/// accepted (deprecated: parameterWarnings() says so).
bool parseWinchMode(const std::string& text, WinchMode* mode);

/// Warnings about values that are accepted but deprecated (today: winch_mode `passive`), one per value,
/// for the loaders to show; empty when there is none.
std::vector<std::string> parameterWarnings(const std::vector<std::pair<std::string, ParamValue>>& values);
/// Parses a drag model name; returns false for an unknown name.
bool parseDragModel(const std::string& text, DragModel* model);

}  // namespace rov_tether
