#include "rov_tether/core/spool_drum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rov_tether
{

namespace
{

/// The characteristic `points` (n of them, the last continued at s = high) with the motor's stall pull: at
/// `stall` the motor gives way, so the drum stops reeling in whatever the acceleration limit would have had
/// it do, and pulled harder it is back-driven, paying out up to `top` (>= 0). Returns the new count.
std::size_t applyStall(std::array<std::pair<double, double>, 8>& points, std::size_t n, double high, double stall,
                       double top)
{
  if (!std::isfinite(stall))
  {
    return n;
  }
  std::array<std::pair<double, double>, 8> out;
  std::size_t m = 0;
  bool stalled = false;
  auto stallAt = [&](double s)  // the drum turns at s up to the stall pull, then gives way up to `top`
  {
    if (s < top)
    {
      out[m++] = {stall, s};
    }
    out[m++] = {stall, std::max(s, top)};
    stalled = true;
  };
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto [lambda, s] = points[i];
    if (!stalled && lambda >= stall)
    {
      double at = s;  // s where the force reaches the stall pull
      if (i > 0 && lambda > points[i - 1].first)
      {
        const auto [l0, s0] = points[i - 1];
        at = s0 + (s - s0) * (stall - l0) / (lambda - l0);
      }
      else if (i > 0)
      {
        at = points[i - 1].second;  // a drum turning at this force: it stalls at its start
      }
      stallAt(at);
    }
    if (stalled)
    {
      out[m++] = {lambda, std::max(s, top)};
    }
    else
    {
      out[m++] = {lambda, s};
    }
  }
  if (!stalled)
  {
    stallAt(high);  // the last point's ray (s = high) reaches the stall pull
  }
  points = out;
  return m;
}

}  // namespace

void SpoolDrum::prepare(double alpha)
{
  alpha_ = alpha;
  const double low = std::min(min_payout, max_payout);
  const double high = max_payout;
  const double rest = std::clamp(0.0, low, high);  // the drum standing, as far as the limits let it
  // The characteristic s(lambda) for lambda >= 0 as points (lambda, s) joined by straight lines, the last
  // one continued at s = high; points with the same lambda are a drum turning at a fixed force.
  std::array<std::pair<double, double>, 8> points;
  std::size_t n = 0;
  if (inertia > 0.0)
  {
    // s = clamp(coast + (lambda - brake) / m, low, high).
    auto s_of = [&](double lambda) { return std::clamp(coast + (lambda - brake) / inertia, low, high); };
    points[n++] = {0.0, s_of(0.0)};
    const double leaves_low = brake + inertia * (low - coast);
    const double reaches_high = brake + inertia * (high - coast);
    if (leaves_low > 0.0)
    {
      points[n++] = {leaves_low, low};
    }
    if (reaches_high > 0.0)
    {
      points[n++] = {reaches_high, high};
    }
  }
  else
  {
    if (floor > 0.0)
    {
      points[n++] = {0.0, low};  // reels in as fast as it can below the floor
      points[n++] = {floor, low};
      points[n++] = {floor, rest};
    }
    else
    {
      points[n++] = {0.0, rest};
    }
    const double pays = std::max(brake, floor > 0.0 ? floor : 0.0);
    if (pays > 0.0)
    {
      points[n++] = {pays, rest};
    }
    points[n++] = {pays, high};
  }
  const double top = std::max({slip, high, 0.0});
  n = applyStall(points, n, high, std::max(stall, 0.0), top);
  // The law lambda(c), c = s + alpha lambda: the slack piece first, then one piece between each two points,
  // then the last point's ray (s = high: the segment stretches again).
  slack_payout_ = points[0].second;
  count_ = 0;
  pieces_[count_++] = {-1e300, 0.0, 0.0};
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    const double c0 = points[i].second + alpha * points[i].first;
    const double c1 = points[i + 1].second + alpha * points[i + 1].first;
    if (c1 > c0)
    {
      pieces_[count_++] = {c0, points[i].first, (points[i + 1].first - points[i].first) / (c1 - c0)};
    }
  }
  const auto& last = points[n - 1];
  pieces_[count_++] = {last.second + alpha * last.first, last.first, 1.0 / alpha};
  // The slack piece ends where the first piece starts (c = s(0)).
}

std::size_t SpoolDrum::pieceOf(double c) const
{
  std::size_t piece = 0;
  for (std::size_t i = 1; i < count_; ++i)
  {
    if (c > pieces_[i].c0)
    {
      piece = i;
    }
  }
  return piece;
}

SpoolDrum::Row SpoolDrum::row(std::size_t piece) const
{
  const Piece& p = pieces_[piece];
  if (p.slope == 0.0)
  {
    return {true, p.lambda0, 0.0};
  }
  // lambda = lambda0 + slope (c - c0)  <=>  c - (c0 - lambda0 / slope) - lambda / slope = 0.
  return {false, p.c0 - p.lambda0 / p.slope, 1.0 / p.slope};
}

double SpoolDrum::force(double c) const
{
  const Piece& p = pieces_[pieceOf(c)];
  return p.lambda0 + p.slope * (c - p.c0);
}

double SpoolDrum::stiffness(double c) const { return pieces_[pieceOf(c)].slope; }

double SpoolDrum::energy(double c) const
{
  // The integral of the piecewise linear force from the start of the first loaded piece: trapezoids.
  double total = 0.0;
  for (std::size_t i = 1; i < count_ && c > pieces_[i].c0; ++i)
  {
    const double from = pieces_[i].c0;
    const double to = i + 1 < count_ ? std::min(c, pieces_[i + 1].c0) : c;
    total += 0.5 * (force(from) + force(to)) * (to - from);
  }
  return total;
}

double SpoolDrum::stretchOff(double c, double lambda) const
{
  // The law is continuous and does not fall, so the stretches that give lambda are one interval, on the side of c
  // where the force moves towards lambda: walk the pieces that way from c's own to the first sloped one that
  // reaches lambda (a piece of a fixed force equal to lambda is entered from the sloped piece it meets).
  const double here = force(c);
  if (here == lambda)
  {
    return 0.0;
  }
  const std::size_t own = pieceOf(c);
  for (std::size_t i = own; here < lambda && i < count_; ++i)
  {
    const Piece& p = pieces_[i];
    const double end = i + 1 < count_ ? pieces_[i + 1].c0 : std::numeric_limits<double>::infinity();
    const bool sloped = p.slope > 0.0;
    if (!sloped && p.lambda0 >= lambda)
    {
      // A piece of a fixed force that gives lambda (the sloped piece before it reached lambda, by a rounding past
      // its end): from its start.
      return std::max(p.c0, c) - c;
    }
    const double at = sloped ? p.c0 + (lambda - p.lambda0) / p.slope : 0.0;  // where it gives lambda
    if (sloped && at <= end)
    {
      return std::max(at, c) - c;  // the last piece (the segment's own stiffness, 1 / alpha) always reaches it
    }
  }
  for (std::size_t i = own + 1; here > lambda && i-- > 0;)
  {
    const Piece& p = pieces_[i];
    const bool sloped = p.slope > 0.0;
    const double at = sloped ? p.c0 + (lambda - p.lambda0) / p.slope : 0.0;
    if (sloped && at >= p.c0)
    {
      return c - std::min(at, c);
    }
  }
  return std::numeric_limits<double>::infinity();  // lambda below 0: the slack piece's force is 0
}

double SpoolDrum::forceAgainst(double a, double b) const
{
  // On piece i: lambda = lambda0 + slope (a - b lambda - c0), so lambda = (lambda0 + slope (a - c0)) /
  // (1 + slope b); it is the answer when the stretch a - b lambda lies on that piece.
  for (std::size_t i = count_; i-- > 0;)
  {
    const Piece& p = pieces_[i];
    const double lambda = (p.lambda0 + p.slope * (a - p.c0)) / (1.0 + p.slope * b);
    const double c = a - b * lambda;
    if (i == 0 || c >= p.c0)
    {
      return lambda;
    }
  }
  return 0.0;
}

double SpoolDrum::payoutAt(double c) const
{
  if (pieceOf(c) == 0)
  {
    return slack_payout_;  // a slack segment does not hold the drum: it coasts, stands or reels in
  }
  // A drum pulled past its stall pull gives way: up to `slip` whatever the limits would have had it do.
  const double high = std::isfinite(stall) ? std::max({max_payout, slip, 0.0}) : max_payout;
  return std::clamp(c - alpha_ * force(c), std::min(min_payout, max_payout), high);
}

}  // namespace rov_tether
