// rostest of tether_node (test/ros/node.test): the test owns simulated time (/clock) and the vehicle
// pose, and waits on topics and services with wall-clock timeouts, never on fixed sleeps. Every case
// sets up what it needs (Harness::startFresh, moveVehicleOut), so each passes alone and in any order
// (checked with --gtest_filter on each case and --gtest_shuffle).
#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <rosgraph_msgs/Log.h>
#include <std_srvs/Trigger.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include "rov_tether/GetTension.h"
#include "rov_tether/SetWinch.h"
#include "rov_tether/TetherState.h"
#include "wait_for.hpp"

namespace
{

constexpr double kTick = 0.005;  // simulated seconds per /clock message

/// Drives the node: publishes /clock and rov_pose, records what the node publishes.
class Harness
{
 public:
  Harness()
  {
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    pose_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("/rov_pose", 10);
    state_sub_ = nh_.subscribe("/tether_node/state", 100, &Harness::onState, this);
    marker_sub_ = nh_.subscribe("/tether_node/markers", 10, &Harness::onMarkers, this);
    wrench_sub_ = nh_.subscribe("/tether_node/wrench", 10, &Harness::onWrench, this);
    vehicle_wrench_sub_ = nh_.subscribe("/tether_node/wrench_vehicle", 10, &Harness::onVehicleWrench, this);
    tf_sub_ = nh_.subscribe("/tf", 100, &Harness::onTf, this);
    diagnostics_sub_ = nh_.subscribe("/diagnostics", 10, &Harness::onDiagnostics, this);
    rosout_sub_ = nh_.subscribe("/rosout", 100, &Harness::onLog, this);
  }

  /// Spins until `done` or the wall timeout [s]; returns whether `done` became true.
  bool waitFor(const std::function<bool()>& done, double timeout) { return rov_tether::test::waitFor(done, timeout); }

  /// Advances simulated time by `seconds`, publishing the clock and, when `pose` is set, a vehicle pose
  /// every other tick; waits until the node has published a state at or after the new time.
  bool drive(double seconds, const std::function<geometry_msgs::Pose(double)>& pose = nullptr)
  {
    const int ticks = static_cast<int>(std::round(seconds / kTick));
    for (int k = 0; k < ticks; ++k)
    {
      sim_time_ += kTick;
      publishClock();
      if (pose && k % 2 == 0)
      {
        geometry_msgs::PoseStamped msg;
        msg.header.stamp = ros::Time(sim_time_);
        msg.header.frame_id = "world";
        msg.pose = pose(sim_time_);
        pose_pub_.publish(msg);
      }
      ros::spinOnce();
      ros::WallDuration(0.0002).sleep();  // lets the node keep up with the clock
      // The clock waits for a node that falls behind (a sanitizer build on a busy machine): beyond max_lag
      // (1 s) it would skip ahead with the cable held, and a winch would pay out less than the time allows.
      if (k % 50 == 49 && state_count_ > 0)
      {
        const double behind = sim_time_ - 0.5;
        waitFor([&] { return state_.header.stamp.toSec() >= behind; }, 2.0);
      }
    }
    const double target = sim_time_ - 0.2;  // the node's physics runs interpolation_delay (0.1 s) behind
    return waitFor([&] { return state_count_ > 0 && state_.header.stamp.toSec() >= target; }, 10.0) ||
           nudgeUntilState(target);
  }

  void setTime(double t)
  {
    sim_time_ = t;
    publishClock();
  }

  /// Broadcasts world -> boat (5 m along x) at the current simulated time.
  void broadcastBoat()
  {
    geometry_msgs::TransformStamped boat;
    boat.header.stamp = ros::Time(sim_time_);
    boat.header.frame_id = "world";
    boat.child_frame_id = "boat";
    boat.transform.translation.x = 5.0;
    boat.transform.rotation.w = 1.0;
    broadcaster_.sendTransform(boat);
  }

  void publishPose(const geometry_msgs::Pose& pose, const std::string& frame = "world", double age = 0.0)
  {
    geometry_msgs::PoseStamped msg;
    msg.header.stamp = ros::Time(sim_time_ - age);
    msg.header.frame_id = frame;
    msg.pose = pose;
    pose_pub_.publish(msg);
  }

  /// The node up, with default.yaml's parameters (dynamic_reconfigure and the winch restored), the
  /// tether just reset and the vehicle attached at home, 1.58 m from the spool with 2 m deployed.
  void startFresh();
  /// From home, the vehicle goes out 4 m along x at 0.4 m/s and stops 5.5 m out (deployed above 5 m).
  void moveVehicleOut();
  /// ~set_winch to `mode` (brake, locked, ...) at `speed` [m/s] (speed mode), no target, default.yaml's brake and
  /// target tensions.
  void setWinch(const std::string& mode, double speed = 0.0);
  /// A client of ~set_winch, once the service is there (10 s at most).
  void winchClient(ros::ServiceClient* client);

  ros::NodeHandle nh_;
  rov_tether::TetherState state_;
  int state_count_ = 0;
  visualization_msgs::MarkerArray markers_;
  int marker_count_ = 0;
  geometry_msgs::WrenchStamped wrench_;
  int wrench_count_ = 0;
  geometry_msgs::WrenchStamped vehicle_wrench_;
  int vehicle_wrench_count_ = 0;
  std::map<std::string, geometry_msgs::TransformStamped> transforms_;  ///< Last /tf transform per child frame.
  bool started_ = false;
  bool saw_tether_diagnostics_ = false;
  long rejected_poses_ = -1;                ///< "rejected poses" of the last tether diagnostics (-1: none yet).
  std::string tether_summary_;              ///< Message of the last tether diagnostics.
  long short_of_tolerance_ = -1;            ///< "sub-steps short of solver_tolerance" of the last (-1: none yet).
  int tether_diagnostics_count_ = 0;        ///< Tether diagnostics statuses received.
  std::vector<std::string> node_warnings_;  ///< The node's WARN lines on /rosout, in order.
  /// How many of the node's WARN lines so far hold `text`.
  long warningsSaying(const std::string& text) const
  {
    return std::count_if(node_warnings_.begin(), node_warnings_.end(),
                         [&](const std::string& line) { return line.find(text) != std::string::npos; });
  }
  /// The last of the node's WARN lines that holds `text` ("" for none).
  std::string lastWarningSaying(const std::string& text) const
  {
    const auto line = std::find_if(node_warnings_.rbegin(), node_warnings_.rend(),
                                   [&](const std::string& l) { return l.find(text) != std::string::npos; });
    return line == node_warnings_.rend() ? "" : *line;
  }
  double sim_time_ = 1000.0;

 private:
  void publishClock()
  {
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(sim_time_);
    clock_pub_.publish(clock);
  }

  /// Keeps the clock ticking (a timer may have missed the last message) until a fresh state arrives.
  bool nudgeUntilState(double target)
  {
    for (int k = 0; k < 200; ++k)
    {
      sim_time_ += kTick;
      publishClock();
      if (waitFor([&] { return state_count_ > 0 && state_.header.stamp.toSec() >= target; }, 0.05))
      {
        return true;
      }
    }
    return false;
  }

  void onState(const rov_tether::TetherState& msg)
  {
    state_ = msg;
    ++state_count_;
  }
  void onMarkers(const visualization_msgs::MarkerArray& msg)
  {
    markers_ = msg;
    ++marker_count_;
  }
  void onWrench(const geometry_msgs::WrenchStamped& msg)
  {
    wrench_ = msg;
    ++wrench_count_;
  }
  void onVehicleWrench(const geometry_msgs::WrenchStamped& msg)
  {
    vehicle_wrench_ = msg;
    ++vehicle_wrench_count_;
  }
  void onTf(const tf2_msgs::TFMessage& msg)
  {
    for (const auto& t : msg.transforms)
    {
      transforms_[t.child_frame_id] = t;
    }
  }
  void onLog(const rosgraph_msgs::Log& msg)
  {
    if (msg.name == "/tether_node" && msg.level == rosgraph_msgs::Log::WARN)
    {
      node_warnings_.push_back(msg.msg);
    }
  }
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray& msg)
  {
    for (const auto& status : msg.status)
    {
      if (status.name.find("tether") != std::string::npos)
      {
        saw_tether_diagnostics_ = true;
        ++tether_diagnostics_count_;
        tether_summary_ = status.message;
      }
      for (const auto& kv : status.values)
      {
        if (kv.key == "rejected poses")
        {
          rejected_poses_ = std::stol(kv.value);
        }
        if (kv.key == "sub-steps short of solver_tolerance")
        {
          short_of_tolerance_ = std::stol(kv.value);
        }
      }
    }
  }

  ros::Publisher clock_pub_;
  ros::Publisher pose_pub_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::Subscriber state_sub_;
  ros::Subscriber marker_sub_;
  ros::Subscriber wrench_sub_;
  ros::Subscriber vehicle_wrench_sub_;
  ros::Subscriber tf_sub_;
  ros::Subscriber diagnostics_sub_;
  ros::Subscriber rosout_sub_;
};

Harness* harness = nullptr;

geometry_msgs::Pose poseAt(double x, double y, double z)
{
  geometry_msgs::Pose pose;
  pose.position.x = x;
  pose.position.y = y;
  pose.position.z = z;
  pose.orientation.w = 1.0;
  return pose;
}

/// The vehicle near the spool: 1.5 m away, 0.5 m down.
geometry_msgs::Pose home(double /*t*/) { return poseAt(1.5, 0.0, -0.5); }

/// A dynamic_reconfigure request setting the given fields.
dynamic_reconfigure::Reconfigure reconfigure(const std::vector<std::pair<std::string, double>>& doubles,
                                             const std::vector<std::pair<std::string, int>>& ints,
                                             const std::vector<std::pair<std::string, std::string>>& strings = {})
{
  dynamic_reconfigure::Reconfigure srv;
  for (const auto& [name, value] : doubles)
  {
    dynamic_reconfigure::DoubleParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.doubles.push_back(p);
  }
  for (const auto& [name, value] : ints)
  {
    dynamic_reconfigure::IntParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.ints.push_back(p);
  }
  for (const auto& [name, value] : strings)
  {
    dynamic_reconfigure::StrParameter p;
    p.name = name;
    p.value = value;
    srv.request.config.strs.push_back(p);
  }
  return srv;
}

double configDouble(const dynamic_reconfigure::Config& config, const std::string& name)
{
  for (const auto& p : config.doubles)
  {
    if (p.name == name)
    {
      return p.value;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

int configInt(const dynamic_reconfigure::Config& config, const std::string& name)
{
  for (const auto& p : config.ints)
  {
    if (p.name == name)
    {
      return p.value;
    }
  }
  return std::numeric_limits<int>::min();
}

void Harness::startFresh()
{
  if (!started_)
  {
    // Start the clock and wait for the node to come up (a fresh state after it got a pose).
    ASSERT_TRUE(waitFor(
        [&]
        {
          setTime(sim_time_ + kTick);
          publishPose(home(0));
          return state_count_ > 0 && state_.vehicle_attached;
        },
        60.0))
        << "no ~state with a vehicle from tether_node";
    started_ = true;
  }
  // default.yaml's values of what the cases change, and its brake winch without a target.
  ros::ServiceClient parameters = nh_.serviceClient<dynamic_reconfigure::Reconfigure>("/tether_node/set_parameters");
  ASSERT_TRUE(parameters.waitForExistence(ros::Duration(10.0)));
  auto defaults = reconfigure({{"drag", 0.9}, {"max_winch_pull", 0.0}}, {{"iterations", 10}}, {{"solver", "direct"}});
  ASSERT_TRUE(parameters.call(defaults));
  ASSERT_NO_FATAL_FAILURE(setWinch("brake"));
  // A reset detaches the vehicle; the next pose attaches it at home on a cable laid out afresh.
  ros::ServiceClient reset = nh_.serviceClient<std_srvs::Trigger>("/tether_node/reset");
  ASSERT_TRUE(reset.waitForExistence(ros::Duration(10.0)));
  std_srvs::Trigger trigger;
  ASSERT_TRUE(reset.call(trigger) && trigger.response.success);
  ASSERT_TRUE(drive(1.0, home));
  ASSERT_TRUE(state_.vehicle_attached);
  // Laid out at initial_deployed_length, 2 m, which the brake keeps (the vehicle, 1.58 m out, pulls nothing).
  ASSERT_NEAR(state_.deployed_length, 2.0, 1e-9);
  ASSERT_EQ(state_.iterations, 10u);
  ASSERT_EQ(state_.solver, "direct");
}

void Harness::winchClient(ros::ServiceClient* client)
{
  *client = nh_.serviceClient<rov_tether::SetWinch>("/tether_node/set_winch");
  ASSERT_TRUE(client->waitForExistence(ros::Duration(10.0)));
}

void Harness::setWinch(const std::string& mode, double speed)
{
  ros::ServiceClient winch;
  ASSERT_NO_FATAL_FAILURE(winchClient(&winch));
  rov_tether::SetWinch command;
  command.request.mode = mode;
  command.request.speed = speed;
  command.request.brake_tension = 5.0;  // default.yaml
  command.request.target_tension = 5.0;
  ASSERT_TRUE(winch.call(command) && command.response.success) << command.response.message;
}

void Harness::moveVehicleOut()
{
  const double t0 = sim_time_;
  // 0.4 m/s away from the spool for 10 s: from 1.5 m to 5.5 m along x.
  ASSERT_TRUE(drive(10.0, [t0](double t) { return poseAt(1.5 + 0.4 * std::min(t - t0, 10.0), 0.0, -0.5); }));
  ASSERT_TRUE(drive(0.5, [](double) { return poseAt(5.5, 0.0, -0.5); }));
  ASSERT_GT(state_.deployed_length, 5.0);
}

TEST(TetherNode, StartsAndPublishesStateMarkersWrenchTfAndDiagnostics)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_TRUE(h.drive(1.5, home));
  EXPECT_NEAR(h.state_.deployed_length, 2.0, 0.3);  // default.yaml: 2 m out
  EXPECT_EQ(h.state_.cable_length, 10.0);
  EXPECT_EQ(h.state_.solver, "direct");  // default.yaml
  EXPECT_EQ(h.state_.iterations, 10u);
  EXPECT_EQ(h.state_.winch_mode, "brake");
  EXPECT_DOUBLE_EQ(h.state_.brake_tension, 5.0);
  EXPECT_EQ(h.state_.segment_tension.size(), static_cast<std::size_t>(std::round(h.state_.deployed_length / 0.1)));
  EXPECT_EQ(h.state_.header.frame_id, "world");
  EXPECT_TRUE(
      h.waitFor([&] { return h.marker_count_ > 0 && h.wrench_count_ > 0 && h.vehicle_wrench_count_ > 0; }, 10.0));
  ASSERT_GE(h.markers_.markers.size(), 3u);
  EXPECT_EQ(h.markers_.markers[0].type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(h.markers_.markers[0].points.size(), 2 * h.state_.segment_tension.size());
  EXPECT_EQ(h.vehicle_wrench_.header.frame_id, "rov") << "~wrench_vehicle is in the vehicle's frame (rov_frame)";
  // The vehicle does not turn: the pull in its frame is the pull in the world's.
  EXPECT_NEAR(h.vehicle_wrench_.wrench.force.x, h.wrench_.wrench.force.x,
              1e-3 + 1e-3 * std::abs(h.wrench_.wrench.force.x));
  // tf: the spool outlet and the cable's vehicle end under world (rviz's fixed frame with pose topics).
  ASSERT_TRUE(
      h.waitFor([&] { return h.transforms_.count("tether_spool") && h.transforms_.count("tether_end"); }, 10.0));
  EXPECT_EQ(h.transforms_["tether_spool"].header.frame_id, "world");
  EXPECT_NEAR(h.transforms_["tether_spool"].transform.translation.x, 0.0, 1e-9);  // node.yaml: spool at the origin
  EXPECT_NEAR(h.transforms_["tether_end"].transform.translation.x, 1.5, 1e-6);    // the vehicle at home
  EXPECT_NEAR(h.transforms_["tether_end"].transform.translation.z, -0.5, 1e-6);
  // The updater publishes once per (simulated) second.
  EXPECT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + 0.05);
        return h.saw_tether_diagnostics_;
      },
      20.0));
}

TEST(TetherNode, DeployedLengthGrowsAsTheVehicleMovesAway)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  const double start_length = h.state_.deployed_length;
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  const double distance = std::hypot(5.5, 0.5);
  EXPECT_GT(h.state_.deployed_length, start_length + 3.0);
  EXPECT_GT(h.state_.deployed_length, 0.95 * distance);
  EXPECT_LT(h.state_.deployed_length, 1.25 * distance);
  EXPECT_LT(h.state_.max_tension, 100.0);
}

TEST(TetherNode, GetTensionAnswersAndRefusesBadRequests)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  ros::ServiceClient client = h.nh_.serviceClient<rov_tether::GetTension>("/tether_node/get_tension");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  rov_tether::GetTension srv;
  srv.request.segment = 0;
  srv.request.arc_length_from_vehicle = -1.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.segment, 0u);
  EXPECT_EQ(srv.response.tension, srv.response.tension_spool);
  EXPECT_GT(srv.response.deployed_length, 4.0);

  srv.request.segment = -1;
  srv.request.arc_length_from_vehicle = 0.05;  // in the last segment
  ASSERT_TRUE(client.call(srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_EQ(srv.response.tension, srv.response.tension_vehicle);

  srv.request.segment = 100000;
  srv.request.arc_length_from_vehicle = -1.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("outside"), std::string::npos) << srv.response.message;

  srv.request.segment = -1;
  srv.request.arc_length_from_vehicle = 500.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("outside the deployed cable"), std::string::npos) << srv.response.message;

  srv.request.segment = 3;
  srv.request.arc_length_from_vehicle = 1.0;  // both given
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("exactly one"), std::string::npos) << srv.response.message;
}

TEST(TetherNode, DynamicReconfigureChangesIterationsAndDragAndRefusesContradictions)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ros::ServiceClient client = h.nh_.serviceClient<dynamic_reconfigure::Reconfigure>("/tether_node/set_parameters");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  auto srv = reconfigure({{"drag", 0.5}}, {{"iterations", 3}});
  ASSERT_TRUE(client.call(srv));
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.iterations, 3u);
  EXPECT_DOUBLE_EQ(h.state_.drag, 0.5);

  // winch_speed 3 m/s contradicts max_winch_speed 1 m/s: refused, old values kept.
  auto bad = reconfigure({{"winch_speed", 3.0}}, {});
  ASSERT_TRUE(client.call(bad));
  EXPECT_EQ(configDouble(bad.response.config, "winch_speed"), 0.0);
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.iterations, 3u);

  // Values outside the table's ranges (issue 26, item 6): the server used to clamp them to the .cfg's
  // range before the node saw them, so iterations 0 ran as 1 and drag 7 as 1, silently. Each is refused
  // whole and the old values run on (the Bad input row of docs/reliability.md).
  struct OutOfRange
  {
    std::vector<std::pair<std::string, double>> doubles;
    std::vector<std::pair<std::string, int>> ints;
  };
  for (const OutOfRange& c : std::vector<OutOfRange>{{{}, {{"iterations", 0}}},
                                                     {{}, {{"iterations", 5000}}},
                                                     {{{"noise", 5.0}}, {}},
                                                     {{{"drag", 7.0}}, {}},
                                                     {{{"target_tension", -3.0}}, {}}})
  {
    auto refused = reconfigure(c.doubles, c.ints);
    ASSERT_TRUE(client.call(refused));
    EXPECT_EQ(configInt(refused.response.config, "iterations"), 3);
    EXPECT_DOUBLE_EQ(configDouble(refused.response.config, "drag"), 0.5);
    EXPECT_DOUBLE_EQ(configDouble(refused.response.config, "noise"), 0.0005);  // the default (config/default.yaml)
    EXPECT_DOUBLE_EQ(configDouble(refused.response.config, "target_tension"), 5.0);  // the default
  }
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.iterations, 3u);
  EXPECT_DOUBLE_EQ(h.state_.drag, 0.5);
}

// A live change of solver with a vehicle attached keeps the deployed length and the cable's shape (it
// used to re-lay the cable at initial_deployed_length, 2 m for a vehicle 5.5 m away: 1.4 kN and 660%
// strain with xpbd). The winch is locked and the vehicle holds still, so the cable must stay where it
// is: the same deployed length, strained under 1%, under 10 N (a slack cable at rest carries a few
// newtons at most; a re-lay, kilonewtons).
TEST(TetherNode, SolverChangeKeepsTheCable)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  ASSERT_NO_FATAL_FAILURE(h.setWinch("locked"));
  const auto still = [](double) { return poseAt(5.5, 0.0, -0.5); };
  ASSERT_TRUE(h.drive(1.0, still));
  const double deployed = h.state_.deployed_length;
  ros::ServiceClient client = h.nh_.serviceClient<dynamic_reconfigure::Reconfigure>("/tether_node/set_parameters");
  for (const std::string solver : {"xpbd", "direct"})
  {
    auto change = reconfigure({}, {}, {{"solver", solver}});
    ASSERT_TRUE(client.call(change));
    ASSERT_TRUE(h.drive(1.0, still));
    EXPECT_EQ(h.state_.solver, solver);
    EXPECT_NEAR(h.state_.deployed_length, deployed, 1e-9) << solver;
    EXPECT_LT(h.state_.max_strain, 0.01) << solver;
    EXPECT_LT(h.state_.max_tension, 10.0) << solver;
  }
}

TEST(TetherNode, NanAndUnnormalisedPosesNeitherCrashNorCorrupt)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  // Lock the winch so that the deployed length must stay exactly where it is.
  ASSERT_NO_FATAL_FAILURE(h.setWinch("locked"));
  ASSERT_TRUE(h.drive(0.1, [](double) { return poseAt(5.5, 0.0, -0.5); }));
  const double before = h.state_.deployed_length;
  geometry_msgs::Pose nan_pose = poseAt(std::nan(""), 0.0, -0.5);
  geometry_msgs::Pose bad_quaternion = poseAt(9.0, 9.0, -0.5);
  bad_quaternion.orientation.w = 2.0;
  h.publishPose(nan_pose);
  h.publishPose(bad_quaternion);
  ASSERT_TRUE(h.drive(1.0,
                      [&](double t)
                      {
                        // Every fifth pose is bad; the rest hold the vehicle still.
                        return static_cast<int>(t / kTick) % 5 == 0 ? nan_pose : poseAt(5.5, 0.0, -0.5);
                      }));
  EXPECT_EQ(h.state_.deployed_length, before);
  EXPECT_TRUE(std::isfinite(h.state_.max_tension));
  EXPECT_LT(h.state_.max_strain, 0.1);
  const int markers_before = h.marker_count_;
  ASSERT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + kTick);
        return h.marker_count_ > markers_before + 2;
      },
      10.0));
  for (const auto& p : h.markers_.markers[0].points)
  {
    ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
  }
  const auto& end = h.markers_.markers[0].points.back();
  EXPECT_NEAR(end.x, 5.5, 1e-6);  // the vehicle end stayed where the good poses put it
}

// Every kind of bad pose of the README's table is refused, counted in diagnostics and leaves the cable
// where the good poses put it: far beyond the model's range, older than the last pose, in a frame tf
// does not know, and in a known frame but older than the tf buffer.
TEST(TetherNode, BadPosesAreRefusedAndCounted)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  // A moving frame "boat" (transforms exist only from now on), broadcast on every tick. The broadcaster
  // belongs to the harness, so the node's tf listener has long been connected to it.
  auto boatAndVehicle = [&](double)
  {
    h.broadcastBoat();
    return poseAt(5.5, 0.0, -0.5);
  };
  // First the node must know the boat: a boat pose at a current stamp is accepted (retried while the tf
  // messages are still on their way, e.g. under the sanitizers).
  ASSERT_TRUE(h.drive(1.0, boatAndVehicle));
  ASSERT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + kTick);
        return h.rejected_poses_ >= 0;
      },
      10.0));
  bool boat_known = false;
  for (int attempt = 0; attempt < 5 && !boat_known; ++attempt)
  {
    const long before_attempt = h.rejected_poses_;
    ASSERT_TRUE(h.drive(0.1, boatAndVehicle));
    h.setTime(h.sim_time_ + kTick);  // a stamp newer than every world pose so far
    h.broadcastBoat();
    h.waitFor([] { return false; }, 0.1);  // the transform at exactly that stamp reaches the node first
    h.publishPose(poseAt(0.5, 0.0, -0.5), "boat");
    ASSERT_TRUE(h.drive(1.2, boatAndVehicle));  // a diagnostics period later
    boat_known = h.rejected_poses_ == before_attempt;
  }
  ASSERT_TRUE(boat_known) << "a current pose in the boat frame was never accepted";

  const long before = h.rejected_poses_;
  const double deployed = h.state_.deployed_length;
  h.publishPose(poseAt(2e6, 0.0, -0.5));                 // 2000 km out: beyond +-1e6 m
  h.publishPose(poseAt(5.5, 0.0, -0.5), "world", 30.0);  // older than the last pose
  h.publishPose(poseAt(0.5, 0.0, -0.5), "nowhere");      // a frame tf does not know
  h.publishPose(poseAt(0.5, 0.0, -0.5), "boat", 500.0);  // a known frame, older than the tf buffer
  ASSERT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + kTick);
        h.broadcastBoat();
        h.publishPose(poseAt(5.5, 0.0, -0.5));
        return h.rejected_poses_ >= before + 4;
      },
      20.0))
      << "rejected poses: " << h.rejected_poses_ << ", before: " << before;
  EXPECT_EQ(h.rejected_poses_, before + 4);
  ASSERT_TRUE(h.drive(0.3, boatAndVehicle));
  EXPECT_NEAR(h.state_.deployed_length, deployed, 0.05);
  EXPECT_LT(h.state_.max_strain, 0.1);
}

TEST(TetherNode, SetWinchGoesToATargetLengthAndRefusesBadCommands)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  ros::ServiceClient client;
  ASSERT_NO_FATAL_FAILURE(h.winchClient(&client));
  rov_tether::SetWinch srv;
  srv.request.mode = "speed";
  srv.request.speed = 0.5;
  srv.request.target_length = 7.0;
  ASSERT_TRUE(client.call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_TRUE(h.drive(4.0, [](double) { return poseAt(5.5, 0.0, -0.5); }));
  EXPECT_NEAR(h.state_.deployed_length, 7.0, 1e-6);
  EXPECT_EQ(h.state_.winch_mode, "speed");
  EXPECT_NEAR(h.state_.target_length, 7.0, 1e-9);
  // A request of one field keeps the target in force (with mode "" a 0 keeps what is in force: the node handed the
  // rules no target, and the request cleared it).
  rov_tether::SetWinch one;
  one.request.brake_tension = 7.0;
  ASSERT_TRUE(client.call(one));
  ASSERT_TRUE(one.response.success) << one.response.message;
  ASSERT_TRUE(h.drive(0.2, [](double) { return poseAt(5.5, 0.0, -0.5); }));
  EXPECT_EQ(h.state_.winch_mode, "speed");
  EXPECT_NEAR(h.state_.target_length, 7.0, 1e-9);

  srv.request.mode = "fast";
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  srv.request.mode = "speed";
  srv.request.target_length = 50.0;  // beyond the 10 m cable
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("target_length"), std::string::npos);
  srv.request.speed = 5.0;  // beyond max_winch_speed
  srv.request.target_length = 0.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);

  srv.request.mode = "passive";  // the old name of strain: accepted, and the answer says it is deprecated
  srv.request.speed = 0.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  EXPECT_NE(srv.response.message.find("deprecated"), std::string::npos) << srv.response.message;
}

// A ~set_winch request refused for a parameter the service has no field for says which and how to change it: a
// constant_tension target of 100 N with max_winch_pull 50 N (set by dynamic_reconfigure) is refused, as the motor
// gives way below the band's lower edge, target_tension - tension_deadband = 100 - 1 = 99 N (default.yaml's 1 N
// deadband; Params.AWinchPullBelowTheTensionBandIsRefused). The answer names max_winch_pull, its value now, that it
// is no field of ~set_winch and the dynparam command for this node's server (it named the value and the bound but
// not where to change it, and SetWinch has no such field). Following it, max_winch_pull 99 N (the edge is taken),
// the same request is taken and ~state shows the new mode and target. A refusal about the request's own field (a
// speed past max_winch_speed) gets no such hint.
TEST(TetherNode, SetWinchRefusedForMaxWinchPullSaysHowToChangeIt)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ros::ServiceClient parameters = h.nh_.serviceClient<dynamic_reconfigure::Reconfigure>("/tether_node/set_parameters");
  ASSERT_TRUE(parameters.waitForExistence(ros::Duration(10.0)));
  auto pull = reconfigure({{"max_winch_pull", 50.0}}, {});
  ASSERT_TRUE(parameters.call(pull));
  ASSERT_DOUBLE_EQ(configDouble(pull.response.config, "max_winch_pull"), 50.0);  // taken: a brake has no stall pull
  ros::ServiceClient client;
  ASSERT_NO_FATAL_FAILURE(h.winchClient(&client));
  rov_tether::SetWinch srv;
  srv.request.mode = "constant_tension";
  srv.request.target_tension = 100.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  const std::string& message = srv.response.message;
  EXPECT_NE(message.find("max_winch_pull = 50: in constant_tension mode must be 0 (derived) or at least "
                         "target_tension - tension_deadband = 100 - 1 = 99"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("max_winch_pull (now 50.0) is no field of ~set_winch: change it with dynamic_reconfigure "
                         "(rosrun dynamic_reconfigure dynparam set /tether_node max_winch_pull VALUE), then ask again"),
            std::string::npos)
      << message;
  // A refusal about one of the request's own fields names no other place to change it: a speed past
  // max_winch_speed is the request's `speed`.
  rov_tether::SetWinch too_fast;
  too_fast.request.mode = "speed";
  too_fast.request.speed = 15.0;  // within the table's [-20, 20] m/s, past default.yaml's max_winch_speed
  ASSERT_TRUE(client.call(too_fast));
  EXPECT_FALSE(too_fast.response.success);
  EXPECT_NE(too_fast.response.message.find("winch_speed = 15: must be in [-max_winch_speed, max_winch_speed]"),
            std::string::npos)
      << too_fast.response.message;
  EXPECT_EQ(too_fast.response.message.find("is no field"), std::string::npos) << too_fast.response.message;
  // Both problems of a request that has two: the pull with its hint (once), and a speed constant_tension would not
  // act on (winch_service.hpp: speed acts in speed mode only).
  rov_tether::SetWinch both;
  both.request.mode = "constant_tension";
  both.request.target_tension = 100.0;
  both.request.speed = 15.0;
  ASSERT_TRUE(client.call(both));
  EXPECT_FALSE(both.response.success);
  EXPECT_NE(both.response.message.find("max_winch_pull = 50:"), std::string::npos) << both.response.message;
  EXPECT_NE(both.response.message.find("speed = 15 m/s: acts in speed mode only"), std::string::npos)
      << both.response.message;
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.winch_mode, "brake");  // nothing changed

  pull = reconfigure({{"max_winch_pull", 99.0}}, {});
  ASSERT_TRUE(parameters.call(pull));
  ASSERT_DOUBLE_EQ(configDouble(pull.response.config, "max_winch_pull"), 99.0);
  ASSERT_TRUE(client.call(srv));
  EXPECT_TRUE(srv.response.success) << srv.response.message;
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.winch_mode, "constant_tension");
  EXPECT_DOUBLE_EQ(h.state_.target_tension, 100.0);
}

// The brake and constant-tension setpoints go through ~set_winch and come back in ~state; a vehicle faster
// than max_winch_speed (1 m/s in default.yaml) outruns the brake winch: ~state says so and the diagnostics
// warn "the vehicle outruns the winch".
TEST(TetherNode, SetWinchSetsTensionsAndTheVehicleOutrunningItIsReported)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  ros::ServiceClient client;
  ASSERT_NO_FATAL_FAILURE(h.winchClient(&client));
  rov_tether::SetWinch srv;
  srv.request.mode = "brake";
  srv.request.brake_tension = -1.0;
  ASSERT_TRUE(client.call(srv));
  EXPECT_FALSE(srv.response.success);
  EXPECT_NE(srv.response.message.find("brake_tension"), std::string::npos) << srv.response.message;
  srv.request.brake_tension = 3.0;
  srv.request.target_tension = 12.0;
  ASSERT_TRUE(client.call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;
  const double x0 = 5.5;  // where moveVehicleOut left the vehicle
  ASSERT_TRUE(h.drive(0.5, [&](double) { return poseAt(x0, 0.0, -0.5); }));
  EXPECT_EQ(h.state_.winch_mode, "brake");
  EXPECT_DOUBLE_EQ(h.state_.brake_tension, 3.0);
  EXPECT_DOUBLE_EQ(h.state_.target_tension, 12.0);
  srv.request.brake_tension = 0.0;  // keeps 3 N
  srv.request.target_tension = 0.0;
  ASSERT_TRUE(client.call(srv));
  ASSERT_TRUE(srv.response.success) << srv.response.message;

  // 1.5 m/s away from the spool for 2.5 s: the slack goes within about 1 s, then the drum turns at its limit.
  const double start = h.sim_time_;
  bool outrun = false;
  for (int k = 0; k < 25 && !outrun; ++k)
  {
    ASSERT_TRUE(h.drive(0.1, [&](double t) { return poseAt(x0 + 1.5 * (t - start), 0.0, -0.5); }));
    outrun = h.state_.winch_outrun;
  }
  EXPECT_TRUE(outrun);
  EXPECT_DOUBLE_EQ(h.state_.brake_tension, 3.0);
  EXPECT_NEAR(h.state_.winch_speed, 1.0, 0.05);  // measured over the publishing period
  // Held where it stopped: the diagnostics (1 s period) keep the warning for 5 s.
  const double stop = x0 + 1.5 * (h.sim_time_ - start);
  ASSERT_TRUE(h.drive(1.5, [&](double) { return poseAt(stop, 0.0, -0.5); }));
  EXPECT_NE(h.tether_summary_.find("the vehicle outruns the winch"), std::string::npos) << h.tether_summary_;
}

// A `speed` winch reeling in at 0.5 m/s while the vehicle holds still 5.5 m out: once the slack is in, the motor's
// stall pull (default.yaml: max_winch_pull 0, so 1.25 x (5 + 1) = 7.5 N) holds the drum, which cannot reel in at its
// speed; /diagnostics warns of it (as of an outrun winch, for 5 s after: the updater's period is 1 s), and ~state
// shows the drum stopped with the spool tension at the pull (1%).
TEST(TetherNode, ASpeedWinchHeldAtItsStallPullIsReported)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  EXPECT_EQ(h.tether_summary_.find("stall pull"), std::string::npos) << h.tether_summary_;
  ASSERT_NO_FATAL_FAILURE(h.setWinch("speed", -0.5));
  // The slack (deployed less the 5.52 m to the vehicle) is in within a second; then 2.5 s held, past the diagnostics'
  // period.
  ASSERT_TRUE(h.drive(3.5, [](double) { return poseAt(5.5, 0.0, -0.5); }));
  EXPECT_NEAR(h.state_.tension_spool, 7.5, 0.075);
  EXPECT_NEAR(h.state_.winch_speed, 0.0, 1e-3);  // measured over the publishing period
  EXPECT_NE(h.tether_summary_.find("the winch is held at its stall pull (7.5 N): it cannot reel in"), std::string::npos)
      << h.tether_summary_;
}

// A `speed` winch reeling in at 0.5 m/s with the vehicle 0.46 m from the spool (inside min_deployed_length, 0.5 m in
// default.yaml, so nothing pulls: the rod's arc at 0.5 m bends with about EI / R^2 = 2 N, below the motor's 7.5 N
// stall pull; at 0.32 m the tighter bend held the drum at the stall pull, 0.68 m out) slows down and stands at 0.5 m;
// the node says so on /rosout once each time it comes to stand, naming min_deployed_length and winch_speed
// (Tether::winchAtShortest), as the runner does: from 2 m, 1.5 m at 0.5 m/s and 0.5 s of each ramp
// (max_winch_acceleration 1 m/s^2) take 3.5 s; 1.5 s more to spare, then 6 s more standing (past the warnings' 5 s
// throttle) say nothing more.
TEST(TetherNode, ASpeedWinchStandingAtTheShortestLengthIsSaidOnce)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  const auto said = [&] { return h.warningsSaying("the winch stands at min_deployed_length"); };
  const auto before = said();
  const double t0 = h.sim_time_;
  const auto close = [t0](double t)
  {
    const double s = std::min((t - t0) / 2.0, 1.0);  // from home (1.5, 0, -0.5) to (0.45, 0, -0.1) in 2 s
    return poseAt(1.5 - 1.05 * s, 0.0, -0.5 + 0.4 * s);
  };
  ASSERT_TRUE(h.drive(2.0, close));
  EXPECT_EQ(said(), before);
  ASSERT_NO_FATAL_FAILURE(h.setWinch("speed", -0.5));
  ASSERT_TRUE(h.drive(5.0, close));
  EXPECT_NEAR(h.state_.deployed_length, 0.5, 1e-6);
  ASSERT_TRUE(h.waitFor([&] { return said() > before; }, 10.0)) << "no warning on /rosout";
  const std::string line = h.lastWarningSaying("the winch stands at min_deployed_length");
  EXPECT_NE(line.find("min_deployed_length = 0.5 m: winch_speed = -0.5 m/s"), std::string::npos) << line;
  ASSERT_TRUE(h.drive(6.0, close));
  EXPECT_EQ(said(), before + 1);
  EXPECT_NEAR(h.state_.deployed_length, 0.5, 1e-6);
}

// A sub-step the solver stops short of solver_tolerance is reported, not only counted by the runner: /diagnostics
// counts such sub-steps, and warns for 5 s after one that ended above solver_residual_warning (node.yaml: 1e-4).
// With one Newton iteration a step, a moving cable's sub-steps end far above both (residuals up to 0.6 of a
// segment in Runner.CountsTheSubStepsThatStopShortOfTheTolerance: a Newton step leaves at least the segments'
// second-order stretch); back at the default 10 with the vehicle holding still, the warning goes.
TEST(TetherNode, StepsShortOfTheSolverToleranceAreReported)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ros::ServiceClient client = h.nh_.serviceClient<dynamic_reconfigure::Reconfigure>("/tether_node/set_parameters");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  auto one = reconfigure({}, {{"iterations", 1}});
  ASSERT_TRUE(client.call(one));
  const double t0 = h.sim_time_;
  const auto out = [t0](double t) { return poseAt(1.5 + 0.4 * (t - t0), 0.0, -0.5); };
  ASSERT_TRUE(h.drive(2.5, out));
  // A status from after those sub-steps (/diagnostics comes once a simulated second).
  const int seen = h.tether_diagnostics_count_;
  for (int k = 0; k < 10 && h.tether_diagnostics_count_ <= seen; ++k)
  {
    ASSERT_TRUE(h.drive(0.5, out));
  }
  EXPECT_GT(h.short_of_tolerance_, 0);
  EXPECT_NE(h.tether_summary_.find("short of solver_tolerance"), std::string::npos) << h.tether_summary_;
  auto ten = reconfigure({}, {{"iterations", 10}});
  ASSERT_TRUE(client.call(ten));
  const double x = 1.5 + 0.4 * (h.sim_time_ - t0);
  const auto still = [x](double) { return poseAt(x, 0.0, -0.5); };
  // Held still, for up to 30 simulated seconds, until a status without the warning comes (5 s after the last).
  bool gone = false;
  for (int k = 0; k < 60 && !gone; ++k)
  {
    const int before = h.tether_diagnostics_count_;
    ASSERT_TRUE(h.drive(0.5, still));
    gone = h.tether_diagnostics_count_ > before &&
           h.tether_summary_.find("short of solver_tolerance") == std::string::npos;
  }
  EXPECT_TRUE(gone) << h.tether_summary_;
}

TEST(TetherNode, TimeGoingBackwardsResetsTheTether)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  const std::uint32_t resets = h.state_.resets;
  ASSERT_GT(h.state_.deployed_length, 5.0);
  h.setTime(h.sim_time_ - 50.0);  // a bag loops
  ASSERT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + kTick);
        h.publishPose(poseAt(1.5, 0.0, -0.5));
        return h.state_.resets > resets;
      },
      20.0));
  EXPECT_NEAR(h.state_.deployed_length, 2.0, 0.2);
  EXPECT_TRUE(std::isfinite(h.state_.max_tension));
}

// A clock that leaps forwards (a bag skipped, a paused simulator resumed) by more than 5 s resets the
// tether instead of simulating the gap in one burst.
TEST(TetherNode, TimeLeapingForwardResetsTheTether)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  const std::uint32_t resets = h.state_.resets;
  h.setTime(h.sim_time_ + 60.0);
  ASSERT_TRUE(h.waitFor(
      [&]
      {
        h.setTime(h.sim_time_ + kTick);
        h.publishPose(home(0.0));
        return h.state_.resets > resets;
      },
      20.0));
  EXPECT_EQ(h.state_.resets, resets + 1);
  EXPECT_TRUE(std::isfinite(h.state_.max_tension));
}

// After a reset the first pose attaches the vehicle; one 12 m from the spool is beyond the 10 m of cable there is
// (default.yaml): the cable is laid stretched to it, and the node warns of it, with the distance, the cable and the
// strain it is laid at, (12 - 10) / 10 = 0.2 (it was only an over-tension).
TEST(TetherNode, AFirstPoseOutOfTheTethersReachIsWarned)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  const auto said = [&] { return h.warningsSaying("out of the tether's reach"); };
  EXPECT_EQ(said(), 0) << "the vehicle at home, 1.58 m out on 2 m";
  const auto run_out = [&] { return h.warningsSaying("the cable runs out"); };
  const auto run_out_before = run_out();
  ros::ServiceClient client = h.nh_.serviceClient<std_srvs::Trigger>("/tether_node/reset");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  std_srvs::Trigger srv;
  ASSERT_TRUE(client.call(srv) && srv.response.success);
  ASSERT_TRUE(h.drive(0.5, [](double) { return poseAt(12.0, 0.0, 0.0); }));
  ASSERT_TRUE(h.state_.vehicle_attached);
  ASSERT_TRUE(h.waitFor([&] { return said() > 0; }, 10.0)) << "no warning on /rosout";
  EXPECT_EQ(said(), 1);
  const std::string line = h.lastWarningSaying("out of the tether's reach");
  EXPECT_NE(line.find("the vehicle's first position is 12 m from the spool, beyond the 10 m of cable there is: the "
                      "cable is laid stretched to it (strain 0.2)"),
            std::string::npos)
      << line;
  ASSERT_TRUE(h.drive(0.5, [](double) { return poseAt(12.0, 0.0, 0.0); }));
  EXPECT_EQ(run_out(), run_out_before) << "laid out to all of its 10 m, the cable did not run out: no winch paid it";
}

// A vehicle that drives on past all of the cable (default.yaml: 10 m, a 5 N brake paying out behind it, from 2 m)
// runs it out: the node says so on /rosout once, naming cable_length, as the runner does (its /diagnostics said
// only "fully deployed"). Driven from home (1.58 m out) to 11.5 m at 0.5 m/s the cable is all out before the
// vehicle is 10 m from the spool plus the brake's stretch (5 N / EA over 10 m: 0.5 mm), at 18 s at the latest.
TEST(TetherNode, ACableThatRunsOutIsWarned)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  const auto said = [&] { return h.warningsSaying("the cable runs out"); };
  const auto before = said();
  const double t0 = h.sim_time_;
  ASSERT_TRUE(h.drive(22.0, [t0](double t) { return poseAt(1.5 + 0.5 * std::min(t - t0, 20.0), 0.0, -0.5); }));
  EXPECT_GE(h.state_.deployed_length, 10.0 - 1e-6);
  ASSERT_TRUE(h.waitFor([&] { return said() > before; }, 10.0)) << "no warning on /rosout";
  // Still pulling on the run-out cable past the warnings' 5 s throttle: said once, not again.
  ASSERT_TRUE(h.drive(6.0, [](double) { return poseAt(11.5, 0.0, -0.5); }));
  EXPECT_EQ(said(), before + 1);
  const std::string line = h.lastWarningSaying("the cable runs out");
  EXPECT_NE(line.find("all of cable_length = 10 m is paid out"), std::string::npos) << line;
  ASSERT_TRUE(h.drive(0.5, home));
}

TEST(TetherNode, ResetServiceResets)
{
  Harness& h = *harness;
  ASSERT_NO_FATAL_FAILURE(h.startFresh());
  ASSERT_NO_FATAL_FAILURE(h.moveVehicleOut());
  const std::uint32_t resets = h.state_.resets;
  ros::ServiceClient client = h.nh_.serviceClient<std_srvs::Trigger>("/tether_node/reset");
  ASSERT_TRUE(client.waitForExistence(ros::Duration(10.0)));
  std_srvs::Trigger srv;
  ASSERT_TRUE(client.call(srv));
  EXPECT_TRUE(srv.response.success);
  ASSERT_TRUE(h.drive(0.2, home));
  EXPECT_EQ(h.state_.resets, resets + 1);
  EXPECT_LE(h.state_.deployed_length, 2.0 + 1e-6) << "re-laid at initial_deployed_length (then reeled in)";
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "tether_node_test");
  Harness instance;
  harness = &instance;
  return RUN_ALL_TESTS();
}
