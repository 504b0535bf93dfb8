// ~set_winch's rules (winch_service.hpp), without a master: what a request changes, and what it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "rov_tether/ros/winch_service.hpp"

namespace
{
using rov_tether::TetherParams;
using rov_tether::WinchMode;
using rov_tether::ros_layer::winchRequest;

/// The defaults (10 m of cable, max_winch_speed 1 m/s, min_deployed_length 0.5 m) with a speed winch paying out
/// at 0.2 m/s towards 8 m: what a partial request must keep.
struct Running
{
  TetherParams params;
  double target = 8.0;
  Running()
  {
    params.winch_mode = WinchMode::kSpeed;
    params.winch_speed = 0.2;
  }
};

rov_tether::SetWinch::Request request(const std::string& mode, double speed, double target_length)
{
  rov_tether::SetWinch::Request r;
  r.mode = mode;
  r.speed = speed;
  r.target_length = target_length;
  return r;
}

}  // namespace

// A request of one field changes that field only: the srv's rule "0 keeps the current value" for the tensions holds
// for speed and target_length too when the mode is kept ("" ). A brake_tension sent alone used to set the running
// winch's speed to the request's 0 and clear its target, stopping it.
TEST(WinchService, ARequestOfOneFieldKeepsTheRunningSpeedAndTarget)
{
  Running now;
  auto r = request("", 0.0, 0.0);
  r.brake_tension = 7.0;
  ASSERT_EQ(winchRequest(r, &now.params, &now.target, "/n"), "");
  EXPECT_EQ(now.params.winch_mode, WinchMode::kSpeed);
  EXPECT_EQ(now.params.winch_speed, 0.2);
  EXPECT_EQ(now.target, 8.0);
  EXPECT_EQ(now.params.brake_tension, 7.0);

  Running other;  // the speed alone keeps the target, the target alone keeps the speed
  ASSERT_EQ(winchRequest(request("", -0.3, 0.0), &other.params, &other.target, "/n"), "");
  EXPECT_EQ(other.params.winch_speed, -0.3);
  EXPECT_EQ(other.target, 8.0);
  ASSERT_EQ(winchRequest(request("", 0.0, 3.0), &other.params, &other.target, "/n"), "");
  EXPECT_EQ(other.params.winch_speed, -0.3);
  EXPECT_EQ(other.target, 3.0);
}

// Naming mode: speed sets speed and target_length as sent: speed 0 stands the winch, target_length 0 clears the
// target (the only way to send those zeros, documented in SetWinch.srv).
TEST(WinchService, NamingSpeedModeTakesSpeedAndTargetAsSent)
{
  Running now;
  ASSERT_EQ(winchRequest(request("speed", 0.0, 0.0), &now.params, &now.target, "/n"), "");
  EXPECT_EQ(now.params.winch_speed, 0.0);
  EXPECT_TRUE(std::isnan(now.target));
  Running again;
  ASSERT_EQ(winchRequest(request("speed", 0.5, 6.0), &again.params, &again.target, "/n"), "");
  EXPECT_EQ(again.params.winch_speed, 0.5);
  EXPECT_EQ(again.target, 6.0);
}

// A speed or a target length the winch would not act on is refused, not taken and shown in ~state as if it held:
// in any mode but speed, and a target with no speed to go there at. Leaving speed mode clears the target (it would
// otherwise stay in ~state). Nothing the caller holds changes on a refusal.
TEST(WinchService, SpeedAndTargetThatWouldNotActAreRefused)
{
  for (const char* mode : {"brake", "constant_tension", "locked", "strain"})
  {
    for (const auto& [speed, target, field] : {std::tuple{0.0, 8.0, "target_length = 8 m: acts in speed mode only"},
                                               std::tuple{0.3, 0.0, "speed = 0.3 m/s: acts in speed mode only"}})
    {
      TetherParams params;
      double kept = 5.0;
      const std::string answer = winchRequest(request(mode, speed, target), &params, &kept, "/n");
      EXPECT_NE(answer.find(field), std::string::npos) << mode << ": " << answer;
      EXPECT_NE(answer.find(std::string("would be in ") + mode + " mode"), std::string::npos) << answer;
      EXPECT_EQ(kept, 5.0);  // refused: nothing the caller holds changes
      EXPECT_EQ(params.winch_mode, WinchMode::kBrake);
    }
  }
  TetherParams brake;  // the default mode, kept by "": a target asked of it is refused too
  double none = std::nan("");
  EXPECT_NE(winchRequest(request("", 0.0, 8.0), &brake, &none, "/n").find("acts in speed mode only"),
            std::string::npos);

  TetherParams standing;
  standing.winch_mode = WinchMode::kSpeed;
  double target = std::nan("");
  const std::string answer = winchRequest(request("speed", 0.0, 8.0), &standing, &target, "/n");
  EXPECT_NE(answer.find("target_length = 8 m: needs a speed to go there at"), std::string::npos) << answer;

  Running leaving;
  ASSERT_EQ(winchRequest(request("brake", 0.0, 0.0), &leaving.params, &leaving.target, "/n"), "");
  EXPECT_EQ(leaving.params.winch_mode, WinchMode::kBrake);
  EXPECT_TRUE(std::isnan(leaving.target));
}

// Bad numbers are refused with the value as sent ("nan", not std::to_string's "-nan"), and every problem of a
// request is listed.
TEST(WinchService, BadNumbersAreRefusedAndEveryProblemListed)
{
  Running now;
  std::string answer = winchRequest(request("speed", std::nan(""), 0.0), &now.params, &now.target, "/n");
  EXPECT_EQ(answer, "speed = nan m/s: must be finite");
  auto r = request("", 0.0, 0.0);
  r.brake_tension = -std::nan("");
  answer = winchRequest(r, &now.params, &now.target, "/n");
  EXPECT_EQ(answer, "brake_tension = nan N: must be >= 0 (0 keeps the current value)");
  answer = winchRequest(request("speed", 5.0, 50.0), &now.params, &now.target, "/n");
  EXPECT_NE(answer.find("winch_speed = 5: must be in [-max_winch_speed, max_winch_speed]"), std::string::npos)
      << answer;
  EXPECT_NE(answer.find("target_length = 50 m: must be in [min_deployed_length, cable_length] = [0.5, 10] m"),
            std::string::npos)
      << answer;
}
