#include "rov_tether/tether.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rov_tether
{
namespace
{

/// Particles next to the spool that get no random displacement (the paper's rule against spontaneous
/// release): those of the first two free segments.
constexpr std::size_t kNoiseFreeParticles = 2;
/// Vehicle samples that may wait ahead of the simulation; more are refused (see addVehicleSample).
constexpr std::size_t kMaxVehicleSamples = 1024;
/// The first segment's rest length stays within [kMinFirst, kMaxFirst] x segment_length while a
/// particle can be released or taken back.
constexpr double kMinFirst = 0.5;
constexpr double kMaxFirst = 1.5;
/// A segment strain beyond this is a blow-up (a real cable breaks long before) [-].
constexpr double kDivergenceStrain = 1.0;
constexpr double kPi = 3.14159265358979323846;

std::string joinErrors(const std::vector<std::string>& errors)
{
  std::ostringstream out;
  out << "invalid tether parameters: ";
  for (std::size_t i = 0; i < errors.size(); ++i)
  {
    out << (i ? "; " : "") << errors[i];
  }
  return out.str();
}

/// One axis of the damped Verlet update, paper eq. (6)-(8): x' = x + (x - x_prev) D + a dt^2.
/// Unit vector from particle a to particle b (zero when they coincide).
Position unitVector(const Cable& state, std::size_t a, std::size_t b)
{
  const Position d = state.position(b) - state.position(a);
  const double length = d.norm();
  return length > 0.0 ? Position(d / length) : Position::Zero();
}

void verletAxis(double* __restrict x, double* __restrict previous, std::size_t begin, std::size_t end, double damping,
                double displacement)
{
  for (std::size_t i = begin; i < end; ++i)
  {
    const double next = x[i] + (x[i] - previous[i]) * damping + displacement;
    previous[i] = x[i];
    x[i] = next;
  }
}

}  // namespace

void Cable::resize(std::size_t particles)
{
  for (auto* v : {&x, &y, &z, &px, &py, &pz, &inv_mass})
  {
    v->assign(particles, 0.0);
  }
  const std::size_t segments = particles > 0 ? particles - 1 : 0;
  for (auto* v : {&rest, &stretch_weight, &stretch_lambda})
  {
    v->assign(segments, 0.0);
  }
  const std::size_t bends = particles > 1 ? particles - 2 : 0;
  for (auto* v : {&bend_rest, &bend_weight, &bend_lambda})
  {
    v->assign(bends, 0.0);
  }
  first = 0;
  markDirty(0, particles);
}

void Cable::place(std::size_t i, const Position& p)
{
  x[i] = px[i] = p.x();
  y[i] = py[i] = p.y();
  z[i] = pz[i] = p.z();
}

Tether::Tether(const TetherParams& params, const Position& spool, double start_time) : spool_(spool)
{
  const auto errors = params.validate();
  if (!errors.empty())
  {
    throw std::invalid_argument(joinErrors(errors));
  }
  if (!spool.allFinite() || spool.cwiseAbs().maxCoeff() > kMaxCoordinate || !std::isfinite(start_time) ||
      std::abs(start_time) > kMaxTime)
  {
    throw std::invalid_argument("spool position and start time must be finite (within +-1e6 m, +-1e10 s)");
  }
  time_ = target_time_ = base_time_ = start_time;
  applyParams(params);
  build();
}

Tether::Tether(const TetherParams& params, const Position& spool, const Position& vehicle,
                                   double start_time)
    : Tether(params, spool, start_time)
{
  if (!vehicle.allFinite() || vehicle.cwiseAbs().maxCoeff() > kMaxCoordinate)
  {
    throw std::invalid_argument("vehicle position must be finite and within +-1e6 m");
  }
  vehicle_attached_ = true;
  vehicle_ = vehicle;
  samples_.assign(1, VehicleSample{start_time, vehicle, false});
  layOut(lengthToReach(vehicle));  // as when a first sample attaches: the cable reaches the vehicle
}

void Tether::applyParams(const TetherParams& requested)
{
  const TetherParams params = requested.resolved();
  const bool reseed = params.seed != params_.seed || !solver_;
  const bool new_solver = !solver_ || params.solver != params_.solver;
  params_ = params;
  if (new_solver)
  {
    solver_ = makeSolver(params_.solver);
  }
  if (reseed)
  {
    rng_.reseed(static_cast<std::uint64_t>(params_.seed));
  }
  // The current's variation: a few plane waves of 20-100 m wavelength and 1-5 min period drawn from the
  // seed (its own generator, so the noise sequence does not change), no high-frequency content.
  Xoshiro256Plus waves(static_cast<std::uint64_t>(params_.seed) ^ 0x9e3779b97f4a7c15ULL);
  auto unit = [&waves]
  {
    Position v(waves.symmetric(), waves.symmetric(), waves.symmetric());
    return v.norm() > 1e-6 ? Position(v.normalized()) : Position(Position::UnitX());
  };
  for (auto& mode : current_modes_)
  {
    mode.direction = unit();
    const double wavelength = 60.0 + 40.0 * waves.symmetric();
    const double period = 180.0 + 120.0 * waves.symmetric();
    mode.wave_vector = unit() * (2.0 * kPi / wavelength);
    mode.omega = 2.0 * kPi / period;
    mode.phase = kPi * waves.symmetric();
  }
}

Position Tether::currentAt(const Position& point, double t) const
{
  Position u(params_.current[0], params_.current[1], params_.current[2]);
  if (params_.current_variation > 0.0)
  {
    // Each sine has RMS 1/sqrt(2): the sum of K modes scaled by sqrt(2/K) has RMS current_variation.
    const double scale = params_.current_variation * std::sqrt(2.0 / kCurrentModes);
    for (const auto& mode : current_modes_)
    {
      u += scale * std::sin(mode.wave_vector.dot(point) + mode.omega * t + mode.phase) * mode.direction;
    }
  }
  return u;
}

Status Tether::setParams(const TetherParams& params)
{
  const auto errors = params.validate();
  if (!errors.empty())
  {
    return Status::error(joinErrors(errors));
  }
  const bool rebuild = !sameStructure(params_, params.resolved());
  const double old_step = params_.subStep();
  const bool new_mass = params.effectiveMassPerLength() != params_.effectiveMassPerLength();
  applyParams(params);
  if (rebuild)
  {
    rng_.reseed(static_cast<std::uint64_t>(params_.seed));
    build();
    return Status{true, "cable rebuilt for the new cable_length, segment_length or solver"};
  }
  if (params_.subStep() != old_step)
  {
    // Keep each particle's velocity (x - x_prev) / h across the change of (sub-)step.
    const double ratio = params_.subStep() / old_step;
    for (std::size_t i = state_.first; i < state_.size(); ++i)
    {
      state_.px[i] = state_.x[i] - (state_.x[i] - state_.px[i]) * ratio;
      state_.py[i] = state_.y[i] - (state_.y[i] - state_.py[i]) * ratio;
      state_.pz[i] = state_.z[i] - (state_.z[i] - state_.pz[i]) * ratio;
    }
    base_time_ = time_;
    base_steps_ = steps_;
  }
  if (new_mass)
  {
    refreshDerived(state_.first, state_.size() - 1);
  }
  return Status::success();
}

void Tether::build()
{
  state_.resize(params_.segmentCount() + 1);
  tension_scratch_.reserve(state_.size());
  layOut(params_.initial_deployed_length);
}

void Tether::setDeployedLength(double deployed_length)
{
  const double segment = params_.segment_length;
  const std::size_t n = state_.size();
  // Whole segments beyond the first; the first takes the remainder in [0.5, 1.5) segment lengths.
  const double whole = std::floor((deployed_length - kMinFirst * segment) / segment);
  const std::size_t count = std::clamp<std::size_t>(static_cast<std::size_t>(std::max(whole, 0.0)) + 1, 1, n - 1);
  state_.first = n - 1 - count;
  std::fill(state_.rest.begin(), state_.rest.end(), segment);
  state_.rest[state_.first] = deployed_length - static_cast<double>(count - 1) * segment;
}

void Tether::layOut(double deployed_length)
{
  setDeployedLength(deployed_length);
  const std::size_t n = state_.size();
  const std::size_t f = state_.first;
  for (std::size_t i = 0; i <= f; ++i)
  {
    state_.place(i, spool_);
  }
  // The deployed cable is laid at rest along two straight legs spool -> apex -> end, by arc length.
  const double length = deployedLength();
  Position apex;
  Position end;
  if (vehicle_attached_)
  {
    end = vehicle_;
    const Position chord = vehicle_ - spool_;
    const double distance = chord.norm();
    apex = spool_ + 0.5 * chord;  // taut or stretched: a straight line
    if (distance < length)
    {
      // Slack: a V hanging below the chord (sideways when the chord is vertical).
      const Position direction = distance > 1e-9 ? Position(chord / distance) : Position::UnitX();
      Position side = -Position::UnitZ() + direction * direction.z();
      if (side.norm() < 0.1)
      {
        side = Position::UnitX() - direction * direction.x();
      }
      const double offset = std::sqrt(std::max(0.25 * (length * length - distance * distance), 0.0));
      apex += offset * side.normalized();
    }
  }
  else
  {
    // A free end hangs (or floats, when lighter than water) straight from the spool.
    end = spool_ + (params_.weight_in_water < 0.0 ? 1.0 : -1.0) * length * Position::UnitZ();
    apex = 0.5 * (spool_ + end);
  }
  double arc = 0.0;
  for (std::size_t i = f; i < n; ++i)
  {
    const double fraction = length > 0.0 ? std::min(arc / length, 1.0) : 0.0;
    state_.place(i, fraction <= 0.5 ? Position(spool_ + 2.0 * fraction * (apex - spool_))
                                    : Position(apex + (2.0 * fraction - 1.0) * (end - apex)));
    if (i + 1 < n)
    {
      arc += state_.rest[i];
    }
  }
  if (vehicle_attached_)
  {
    state_.place(n - 1, vehicle_);
  }
  std::fill(state_.stretch_lambda.begin(), state_.stretch_lambda.end(), 0.0);
  std::fill(state_.bend_lambda.begin(), state_.bend_lambda.end(), 0.0);
  refreshDerived(f, n - 1);
}

bool Tether::isPinned(std::size_t i) const
{
  return i <= state_.first || (vehicle_attached_ && i + 1 == state_.size());
}

std::size_t Tether::freeEnd() const { return vehicle_attached_ ? state_.size() - 1 : state_.size(); }

void Tether::refreshDerived(std::size_t lo, std::size_t hi)
{
  const std::size_t n = state_.size();
  const std::size_t f = state_.first;
  lo = std::max(lo, f);
  hi = std::min(hi, n - 1);
  // Bending constraints starting two particles before lo change too.
  state_.markDirty(std::max(lo, f + 2) - 2, hi + 1);
  // Lumped masses: half of each neighbouring segment (a free end carries half a segment).
  for (std::size_t i = lo; i <= hi; ++i)
  {
    const double left = i > f ? state_.rest[i - 1] : 0.0;
    const double right = i + 1 < n ? state_.rest[i] : 0.0;
    const double mass = params_.effectiveMassPerLength() * 0.5 * (left + right);
    state_.inv_mass[i] = isPinned(i) || mass <= 0.0 ? 0.0 : 1.0 / mass;
  }
  auto inverse_sum = [](double a, double b) { return a + b > 0.0 ? 1.0 / (a + b) : 0.0; };
  for (std::size_t j = std::max(lo, f + 1) - 1; j <= hi && j + 1 < n; ++j)
  {
    state_.stretch_weight[j] = inverse_sum(state_.inv_mass[j], state_.inv_mass[j + 1]);
  }
  for (std::size_t j = std::max(lo, f + 2) - 2; j <= hi && j + 2 < n; ++j)
  {
    state_.bend_rest[j] = state_.rest[j] + state_.rest[j + 1];
    state_.bend_weight[j] = inverse_sum(state_.inv_mass[j], state_.inv_mass[j + 2]);
  }
}

Status Tether::setSpoolPosition(const Position& spool)
{
  if (!spool.allFinite() || spool.cwiseAbs().maxCoeff() > kMaxCoordinate)
  {
    return Status::error("spool position rejected: not finite or beyond +-1e6 m");
  }
  spool_ = spool;
  return Status::success();
}

Status Tether::addVehicleSample(double t, const Position& vehicle)
{
  if (!std::isfinite(t) || !vehicle.allFinite() || std::abs(t) > kMaxTime ||
      vehicle.cwiseAbs().maxCoeff() > kMaxCoordinate)
  {
    return Status::error(
        "vehicle sample rejected: time and position must be finite (time within +-1e10 s, "
        "position within +-1e6 m)");
  }
  if (!vehicle_attached_ && samples_.empty())
  {
    // The first sample attaches the vehicle when the simulation reaches its time (see vehicleAt), so
    // when a sample arrives does not change the run.
    samples_.push_back(VehicleSample{t, vehicle, false});
    return Status::success();
  }
  if (!samples_.empty() && t < samples_.back().time)
  {
    std::ostringstream out;
    out << "vehicle sample rejected: time " << t << " s is older than the last sample at " << samples_.back().time
        << " s";
    return Status::error(out.str());
  }
  if (!samples_.empty() && t == samples_.back().time)
  {
    samples_.pop_back();  // a duplicate stamp replaces the sample it repeats
  }
  if (samples_.size() >= kMaxVehicleSamples)
  {
    // Consumed samples are dropped as the simulation passes them, so a full buffer holds samples the
    // simulation has not reached: dropping any of them would make the vehicle jump.
    std::ostringstream out;
    out << "vehicle sample rejected: " << samples_.size() << " samples already wait ahead of the simulation (at "
        << time_ << " s); advance it first";
    return Status::error(out.str());
  }
  const Position& previous = samples_.empty() ? vehicle_ : samples_.back().position;
  const bool jump = (vehicle - previous).norm() > params_.max_vehicle_jump;
  samples_.push_back(VehicleSample{t, vehicle, jump});
  return Status::success();
}

Status Tether::setTargetLength(double length)
{
  if (!std::isnan(length) && !(length >= params_.min_deployed_length && length <= params_.cable_length))
  {
    std::ostringstream out;
    out << "target length " << length << " m rejected: must be in [min_deployed_length, cable_length] = ["
        << params_.min_deployed_length << ", " << params_.cable_length << "] m";
    return Status::error(out.str());
  }
  target_length_ = length;
  return Status::success();
}

void Tether::detachVehicle()
{
  vehicle_attached_ = false;
  samples_.clear();
  refreshDerived(state_.size() - 3, state_.size() - 1);
}

Position Tether::vehicleAt(double t)
{
  if (!vehicle_attached_)
  {
    if (samples_.empty() || samples_.front().time > t)
    {
      return vehicle_;
    }
    vehicle_attached_ = true;  // the first sample's time has come: attach and lay the cable out to it
    vehicle_ = samples_.front().position;
    layOut(lengthToReach(vehicle_));
  }
  bool jumped = false;
  while (samples_.size() >= 2 && samples_[1].time <= t)
  {
    samples_.pop_front();
    jumped = jumped || samples_.front().jump;
    samples_.front().jump = false;
  }
  if (samples_.empty())
  {
    return vehicle_;
  }
  Position target = samples_.front().position;
  if (samples_.size() >= 2 && t > samples_[0].time && !samples_[1].jump)
  {
    const double alpha = (t - samples_[0].time) / (samples_[1].time - samples_[0].time);
    target = samples_[0].position + alpha * (samples_[1].position - samples_[0].position);
  }
  if (jumped)
  {
    // The cable cannot follow a jump physically: re-lay it, at rest, to the new attachment point.
    vehicle_ = target;
    layOut(lengthToReach(target));
    ++jumps_;
  }
  return target;
}

double Tether::lengthToReach(const Position& vehicle) const
{
  if (params_.winch_mode == WinchMode::kLocked)
  {
    return deployedLength();
  }
  return std::clamp(std::max(deployedLength(), (vehicle - spool_).norm()), params_.min_deployed_length,
                    params_.cable_length);
}

Status Tether::advance(double dt, std::size_t* steps)
{
  if (!std::isfinite(dt) || dt < 0.0)
  {
    std::ostringstream out;
    out << "advance rejected: interval " << dt << " s must be finite and >= 0";
    return Status::error(out.str());
  }
  return advanceTo(std::max(target_time_, time_) + dt, steps);
}

Status Tether::advanceTo(double t, std::size_t* steps)
{
  if (!std::isfinite(t) || std::abs(t) > kMaxTime)
  {
    return Status::error("advance rejected: target time must be finite and within +-1e10 s");
  }
  target_time_ = t;
  std::size_t taken = 0;
  while (stepFits(target_time_))
  {
    step();
    ++taken;
  }
  if (steps != nullptr)
  {
    *steps = taken;
  }
  return Status::success();
}

Status Tether::skipTo(double t)
{
  if (!std::isfinite(t) || std::abs(t) > kMaxTime || t < time_)
  {
    std::ostringstream out;
    out << "skip rejected: time " << t << " s must be finite and not before the simulation's " << time_ << " s";
    return Status::error(out.str());
  }
  for (std::size_t i = state_.first; i < state_.size(); ++i)
  {
    state_.px[i] = state_.x[i], state_.py[i] = state_.y[i], state_.pz[i] = state_.z[i];
  }
  if (vehicle_attached_ || !samples_.empty())
  {
    vehicle_ = vehicleAt(t);
    if (vehicle_attached_)
    {
      state_.place(state_.size() - 1, vehicle_);
    }
  }
  time_ = target_time_ = base_time_ = t;
  base_steps_ = steps_;
  return Status::success();
}

void Tether::step()
{
  const double dt = params_.time_step;
  const double next_time = nextStepTime();
  const int substeps = params_.substeps;
  const double h = dt / substeps;
  const std::uint64_t failures = recoveries_;
  for (int k = 1; k <= substeps && recoveries_ == failures; ++k)
  {
    subStep(h, k == substeps ? next_time : next_time - dt + k * h, k == 1);
  }
  last_step_ = h;
  ++steps_;
  time_ = next_time;
  if (recoveries_ == failures && !stateFinite())
  {
    fail("non-finite particle position");
  }
}

void Tether::subStep(double h, double t, bool with_noise)
{
  const std::size_t n = state_.size();
  state_.place(state_.first, spool_);
  if (vehicle_attached_ || !samples_.empty())
  {
    vehicle_ = vehicleAt(t);
  }
  integrate(h, t);
  if (with_noise)
  {
    addNoise(params_.time_step);
  }
  if (vehicle_attached_)
  {
    state_.place(n - 1, vehicle_);
  }
  runWinch(h);
  SolverSettings settings;
  settings.iterations = params_.iterations;
  settings.bending = params_.bending;
  settings.time_step = h;
  settings.axial_stiffness = params_.axial_stiffness;
  settings.bending_stiffness = params_.bending_stiffness;
  settings.over_relaxation = params_.over_relaxation;
  solver_->solve(state_, settings);
  if (!std::isnan(params_.seabed_z))
  {
    applySeabed();
  }
  const double strain = solver_->lastMaxStrain();
  if (!std::isnan(strain) && !(strain < kDivergenceStrain))
  {
    std::ostringstream why;
    why << "lumped_mass diverged (segment strain " << strain << "): the sub-step " << h
        << " s exceeds the critical step " << params_.criticalStep() << " s = segment_length / sqrt(EA / mu)";
    fail(why.str());
  }
}

void Tether::fail(const std::string& why)
{
  ++recoveries_;
  std::ostringstream message;
  message << "t = " << time_ << " s: " << why << "; the cable was re-laid at rest";
  last_failure_ = message.str();
  layOut(std::clamp(deployedLength(), params_.min_deployed_length, params_.cable_length));
}

void Tether::integrate(double h, double t)
{
  const std::size_t begin = state_.first + 1;
  const std::size_t end = freeEnd();
  if (begin >= end)
  {
    return;
  }
  if (params_.drag_model == DragModel::kMorison)
  {
    integrateMorison(h, t);
    return;
  }
  // Net weight in water; a neutrally buoyant cable (the default) does no gravity work at all.
  const double sink =
      params_.weight_in_water != 0.0 ? -params_.weight_in_water / params_.effectiveMassPerLength() * h * h : 0.0;
  const double damping = params_.dampingFactor(h);
  if (params_.current_variation > 0.0)
  {
    // Damping relative to the local water velocity: v' = u + D (v - u).
    for (std::size_t i = begin; i < end; ++i)
    {
      const Position drift = (1.0 - damping) * h * currentAt(state_.position(i), t);
      const double x = state_.x[i], y = state_.y[i], z = state_.z[i];
      state_.x[i] += (x - state_.px[i]) * damping + drift.x();
      state_.y[i] += (y - state_.py[i]) * damping + drift.y();
      state_.z[i] += (z - state_.pz[i]) * damping + drift.z() + sink;
      state_.px[i] = x, state_.py[i] = y, state_.pz[i] = z;
    }
    return;
  }
  // A uniform current (zero by default) is one constant displacement per step.
  const double drift = (1.0 - damping) * h;
  verletAxis(state_.x.data(), state_.px.data(), begin, end, damping, drift * params_.current[0]);
  verletAxis(state_.y.data(), state_.py.data(), begin, end, damping, drift * params_.current[1]);
  verletAxis(state_.z.data(), state_.pz.data(), begin, end, damping, drift * params_.current[2] + sink);
}

void Tether::integrateMorison(double h, double t)
{
  // Morison drag on each particle's share of cable, split into the flow normal and tangential to the
  // cable. The impulse is explicit, h c |r| r, so a cable held against the flow feels exactly the drag,
  // but never more than stops the relative motion (r' = r (1 - min(h c |r| / m, 1))): stable at any step.
  const std::size_t n = state_.size();
  const std::size_t begin = state_.first + 1;
  const std::size_t end = freeEnd();
  const double normal = 0.5 * params_.water_density * params_.normal_drag_coefficient * params_.diameter;
  const double tangential = 0.5 * params_.water_density * params_.tangential_drag_coefficient * kPi * params_.diameter;
  const double sink = -params_.weight_in_water / params_.effectiveMassPerLength() * h * h;
  const bool uniform = params_.current_variation <= 0.0;
  const Position u0(params_.current[0], params_.current[1], params_.current[2]);
  for (std::size_t i = begin; i < end; ++i)
  {
    const Position x = state_.position(i);
    const Position previous(state_.px[i], state_.py[i], state_.pz[i]);
    const Position water = uniform ? u0 : currentAt(x, t);
    const Position relative = (x - previous) / h - water;
    // Tangent from the neighbours' positions before this step (particle i - 1 already moved: its px).
    const Position behind(state_.px[i - 1], state_.py[i - 1], state_.pz[i - 1]);
    Position tangent = (i + 1 < n ? state_.position(i + 1) : x) - behind;
    const double tangent_length = tangent.norm();
    tangent = tangent_length > 0.0 ? Position(tangent / tangent_length) : Position::Zero();
    const double share = 0.5 * (state_.rest[i - 1] + (i + 1 < n ? state_.rest[i] : 0.0));
    const double h_per_mass = state_.inv_mass[i] * h * share;
    Position along = relative.dot(tangent) * tangent;
    Position across = relative - along;
    along *= 1.0 - std::min(h_per_mass * tangential * along.norm(), 1.0);
    across *= 1.0 - std::min(h_per_mass * normal * across.norm(), 1.0);
    Position next = x + (water + along + across) * h;
    next.z() += sink;
    state_.px[i] = x.x(), state_.py[i] = x.y(), state_.pz[i] = x.z();
    state_.x[i] = next.x(), state_.y[i] = next.y(), state_.z[i] = next.z();
  }
}

void Tether::applySeabed()
{
  // Contact: a particle below the seabed is put back on it with no normal velocity, and Coulomb friction
  // limits its sliding this step to what the normal correction allows (position-based friction).
  const double bed = params_.seabed_z;
  const double mu = params_.seabed_friction;
  const std::size_t end = freeEnd();
  for (std::size_t i = state_.first + 1; i < end; ++i)
  {
    if (!(state_.z[i] < bed))
    {
      continue;
    }
    const double depth = bed - state_.z[i];
    state_.z[i] = bed;
    state_.pz[i] = bed;
    const double dx = state_.x[i] - state_.px[i];
    const double dy = state_.y[i] - state_.py[i];
    const double slide = std::sqrt(dx * dx + dy * dy);
    const double keep = slide > mu * depth ? 1.0 - mu * depth / slide : 0.0;
    state_.x[i] = state_.px[i] + keep * dx;
    state_.y[i] = state_.py[i] + keep * dy;
  }
}

void Tether::addNoise(double dt)
{
  const double amplitude = params_.noiseAmplitude(dt);
  if (amplitude <= 0.0)
  {
    return;
  }
  const std::size_t end = freeEnd();
  for (std::size_t i = state_.first + 1 + kNoiseFreeParticles; i < end; ++i)
  {
    state_.x[i] += amplitude * rng_.symmetric();
    state_.y[i] += amplitude * rng_.symmetric();
    state_.z[i] += amplitude * rng_.symmetric();
  }
}

void Tether::runWinch(double dt)
{
  const std::size_t n = state_.size();
  const std::size_t f = state_.first;
  if (params_.winch_mode == WinchMode::kLocked || f + 1 >= n)
  {
    return;
  }
  const double max_change = params_.max_winch_speed * dt;
  const double deployed = deployedLength();
  double change = 0.0;
  if (params_.winch_mode == WinchMode::kSpeed)
  {
    const double speed_change = params_.winch_speed * dt;
    change = std::isnan(target_length_)
                 ? speed_change
                 : std::clamp(target_length_ - deployed, -std::abs(speed_change), std::abs(speed_change));
  }
  else
  {
    // The paper's rule with hysteresis: pay-out starts when the first free segment is stretched past
    // payout_threshold and goes on, up to max_winch_speed, while it stays stretched at all (so a steady
    // pull does not hold the cable at the threshold) and less than the reel-in limit is out (so a
    // vehicle circling at constant distance does not unreel the whole cable). The strain is read after the step's
    // motion and before the constraints pull the segment back (a post-projection reading is biased to zero).
    const double length = (state_.position(f + 1) - state_.position(f)).norm();
    const double strain = length / state_.rest[f] - 1.0;
    const double excess =
        vehicle_attached_ ? deployed - (1.0 + params_.reel_in_slack) * (vehicle_ - spool_).norm() : -1.0;
    paying_out_ = strain > params_.payout_threshold || (paying_out_ && strain > 0.0 && excess < 0.0);
    if (paying_out_)
    {
      change = length - state_.rest[f];
    }
    else if (excess > 0.0)
    {
      change = -excess;  // reel in the slack beyond the limit
    }
  }
  change = std::clamp(change, -max_change, max_change);
  change = std::clamp(change, std::min(0.0, params_.min_deployed_length - deployed),
                      std::max(0.0, params_.cable_length - deployed));
  if (change == 0.0)
  {
    return;
  }
  state_.rest[f] += change;
  const double segment = params_.segment_length;
  if (change > 0.0)
  {
    while (state_.first > 0 && state_.rest[state_.first] > kMaxFirst * segment)
    {
      release();
    }
  }
  else
  {
    while (state_.first + 2 < n && state_.rest[state_.first] < kMinFirst * segment)
    {
      merge();
    }
  }
  refreshDerived(state_.first, state_.first + 2);
}

void Tether::release()
{
  // Particle f leaves the spool: it is placed on the first segment, where the cable already is, with
  // the segment's velocity, so neither the shape nor any constraint error changes.
  const std::size_t f = state_.first;
  const double segment = params_.segment_length;
  const double rest = state_.rest[f];
  const double fraction = (rest - segment) / rest;
  auto along = [fraction, f](std::vector<double>& v) { v[f] = v[f] + fraction * (v[f + 1] - v[f]); };
  for (auto* v : {&state_.x, &state_.y, &state_.z, &state_.px, &state_.py, &state_.pz})
  {
    along(*v);
  }
  state_.first = f - 1;
  state_.place(state_.first, spool_);
  state_.rest[state_.first] = rest - segment;
  state_.rest[f] = segment;
  state_.stretch_lambda[state_.first] = 0.0;
  refreshDerived(state_.first, state_.first + 3);
}

void Tether::merge()
{
  // The first free particle goes back onto the spool; its two segments become one with the summed
  // rest length, so the deployed length does not change.
  const std::size_t f = state_.first;
  state_.rest[f + 1] += state_.rest[f];
  state_.rest[f] = params_.segment_length;
  state_.first = f + 1;
  state_.place(f, spool_);
  state_.place(state_.first, spool_);
  refreshDerived(state_.first, state_.first + 2);
}

bool Tether::stateFinite() const
{
  double sum = 0.0;
  for (std::size_t i = state_.first; i < state_.size(); ++i)
  {
    sum += state_.x[i] + state_.y[i] + state_.z[i];
  }
  return std::isfinite(sum);
}

Status Tether::reset(double time)
{
  if (!std::isfinite(time) || std::abs(time) > kMaxTime)
  {
    std::ostringstream out;
    out << "reset rejected: time " << time << " s must be finite and within +-" << kMaxTime << " s";
    return Status::error(out.str());
  }
  // Detached until the next sample: a replay after a reset starts exactly as the first run did.
  samples_.clear();
  vehicle_attached_ = false;
  paying_out_ = false;
  rng_.reseed(static_cast<std::uint64_t>(params_.seed));
  time_ = target_time_ = base_time_ = time;
  base_steps_ = steps_;
  layOut(params_.initial_deployed_length);
  return Status::success();
}

double Tether::deployedLength() const
{
  // Every deployed segment but the first has the nominal length.
  const std::size_t n = state_.size();
  const std::size_t f = state_.first;
  return state_.rest[f] + static_cast<double>(n - 2 - f) * params_.segment_length;
}

void Tether::copyPositions(std::vector<Position>& out) const
{
  out.resize(deployedParticleCount());
  for (std::size_t k = 0; k < out.size(); ++k)
  {
    out[k] = particle(k);
  }
}

void Tether::computeSegmentTensions(std::vector<double>& out) const
{
  const std::size_t n = state_.size();
  const std::size_t f = state_.first;
  out.assign(n - 1 - f, 0.0);
  if (last_step_ <= 0.0)
  {
    return;  // no step taken yet: no constraint force known
  }
  const double inv_dt2 = 1.0 / (last_step_ * last_step_);
  for (std::size_t j = f; j + 1 < n; ++j)
  {
    // The force carried across the cut between particles j and j+1: the stretch constraint of segment j
    // and the bending constraints (j-1, j+1) and (j, j+2) that span the same cut.
    const Position axis = unitVector(state_, j, j + 1);
    Force carried = state_.stretch_lambda[j] * axis;
    if (j > f && j + 1 < n)
    {
      carried += state_.bend_lambda[j - 1] * unitVector(state_, j - 1, j + 1);
    }
    if (j + 2 < n)
    {
      carried += state_.bend_lambda[j] * unitVector(state_, j, j + 2);
    }
    out[j - f] = carried.dot(axis) * inv_dt2;
  }
}

bool Tether::segmentAtArcLengthFromVehicle(double arc_length, std::size_t* segment) const
{
  if (!std::isfinite(arc_length) || arc_length < 0.0 || arc_length > deployedLength())
  {
    return false;
  }
  // Every segment but the first (at the spool) has the nominal length.
  const std::size_t segments = deployedParticleCount() - 1;
  const double nominal = params_.segment_length;
  const double whole = std::floor(arc_length / nominal);
  *segment = whole >= static_cast<double>(segments - 1) ? 0 : segments - 1 - static_cast<std::size_t>(whole);
  return true;
}

double Tether::arcLengthFromVehicleToSegment(std::size_t k) const
{
  const std::size_t segments = deployedParticleCount() - 1;
  const double nominal = params_.segment_length;
  if (k == 0)
  {
    return static_cast<double>(segments - 1) * nominal + 0.5 * state_.rest[state_.first];
  }
  return (static_cast<double>(segments - 1 - k) + 0.5) * nominal;
}

double Tether::segmentStrain(std::size_t k) const
{
  const std::size_t j = state_.first + k;
  return (state_.position(j + 1) - state_.position(j)).norm() / state_.rest[j] - 1.0;
}

Force Tether::vehicleForce() const
{
  const std::size_t n = state_.size();
  if (!vehicle_attached_ || last_step_ <= 0.0)
  {
    return Force::Zero();
  }
  // A stretched constraint (lambda > 0) pulls the vehicle back towards the cable.
  Force pull = -state_.stretch_lambda[n - 2] * unitVector(state_, n - 2, n - 1);
  if (n >= state_.first + 3)
  {
    pull -= state_.bend_lambda[n - 3] * unitVector(state_, n - 3, n - 1);
  }
  return pull / (last_step_ * last_step_);
}

TetherSummary Tether::summary() const
{
  computeSegmentTensions(tension_scratch_);
  return summarize(tension_scratch_);
}

TetherSummary Tether::summarize(const std::vector<double>& tensions) const
{
  TetherSummary result;
  result.time = time_;
  result.deployed_length = deployedLength();
  if (tensions.empty())
  {
    return result;
  }
  result.tension_spool = tensions.front();
  result.tension_vehicle = tensions.back();
  const auto max_it = std::max_element(tensions.begin(), tensions.end());
  result.max_tension = *max_it;
  result.max_tension_segment = static_cast<std::size_t>(max_it - tensions.begin());
  double strain_sum = 0.0;
  result.max_strain = -1.0;
  for (std::size_t k = 0; k < tensions.size(); ++k)
  {
    const double strain = segmentStrain(k);
    result.max_strain = std::max(result.max_strain, strain);
    strain_sum += std::abs(strain);
  }
  result.mean_strain = strain_sum / static_cast<double>(tensions.size());
  return result;
}

}  // namespace rov_tether
