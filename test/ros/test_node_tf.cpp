// rostest (test/ros/node_tf.test): vehicle pose and spool from tf, attachment offset in the vehicle frame,
// and a bad parameter stopping the node at start with a message naming it.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_ros/transform_broadcaster.h>
#include <unistd.h>
#include <visualization_msgs/MarkerArray.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "rov_tether/TetherState.h"

namespace
{

geometry_msgs::TransformStamped transform(const std::string& child, double x, double y, double z, double yaw,
                                          const ros::Time& stamp)
{
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = "world";
  t.child_frame_id = child;
  t.transform.translation.x = x;
  t.transform.translation.y = y;
  t.transform.translation.z = z;
  t.transform.rotation.z = std::sin(yaw / 2);
  t.transform.rotation.w = std::cos(yaw / 2);
  return t;
}

TEST(TetherNodeTf, FollowsTheVehicleFrameWithItsOrientationAndAMovingSpool)
{
  ros::NodeHandle nh;
  ros::Publisher clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  tf2_ros::TransformBroadcaster broadcaster;
  visualization_msgs::MarkerArray markers;
  int marker_count = 0;
  ros::Subscriber sub =
      nh.subscribe<visualization_msgs::MarkerArray>("/tether_node/markers", 10,
                                                    [&](const visualization_msgs::MarkerArray::ConstPtr& msg)
                                                    {
                                                      markers = *msg;
                                                      ++marker_count;
                                                    });
  rov_tether::TetherState state;
  ros::Subscriber state_sub = nh.subscribe<rov_tether::TetherState>(
      "/tether_node/state", 10, [&](const rov_tether::TetherState::ConstPtr& msg) { state = *msg; });

  // The vehicle sits at (3, 0, -1) facing +y (yaw 90 deg): 0.5 m behind it is (3, -0.5, -1).
  // The ship (spool) drifts from (0, 0, 0) to (0, 1, 0) over 4 s, then stays.
  double t = 500.0;
  double t_ship = 501.0;  // the ship starts drifting 1 s after the transforms appear
  auto tick = [&](double dt)
  {
    t += dt;
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(t);
    clock_pub.publish(clock);
    const double ship_y = std::min(std::max(t - t_ship, 0.0) / 4.0, 1.0);
    broadcaster.sendTransform(transform("rov", 3.0, 0.0, -1.0, M_PI / 2, ros::Time(t)));
    broadcaster.sendTransform(transform("ship", 0.0, ship_y, 0.0, 0.0, ros::Time(t)));
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();  // paces the simulated clock
  };
  // First the frames are missing: the node must keep running, publish the hanging cable and say in
  // /diagnostics that it has no vehicle pose, never crash or attach to garbage.
  std::string diagnostics_message;
  ros::Subscriber diag_sub =
      nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10,
                                                     [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& msg)
                                                     {
                                                       for (const auto& status : msg->status)
                                                       {
                                                         if (status.name.find("tether") != std::string::npos)
                                                         {
                                                           diagnostics_message = status.message;
                                                         }
                                                       }
                                                     });
  double t_missing = t;
  int states_missing = 0;
  ros::Subscriber count_sub = nh.subscribe<rov_tether::TetherState>(
      "/tether_node/state", 10, [&](const rov_tether::TetherState::ConstPtr&) { ++states_missing; });
  const ros::WallTime missing_deadline = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && ros::WallTime::now() < missing_deadline &&
         (diagnostics_message.find("no vehicle pose yet") == std::string::npos || states_missing < 5))
  {
    t_missing += 0.005;
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(t_missing);
    clock_pub.publish(clock);
    ros::spinOnce();
    ros::WallDuration(0.0005).sleep();
  }
  EXPECT_NE(diagnostics_message.find("no vehicle pose yet"), std::string::npos) << diagnostics_message;
  EXPECT_GE(states_missing, 5);
  EXPECT_FALSE(state.vehicle_attached);
  count_sub.shutdown();
  t = t_missing;
  t_ship = t + 1.0;

  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(60.0);
  while (ros::ok() && ros::WallTime::now() < deadline && (t < t_missing + 7.0 || marker_count < 3))
  {
    tick(0.005);
  }
  ASSERT_GE(marker_count, 3) << "no markers from tether_node";
  ASSERT_TRUE(state.vehicle_attached);
  const auto& points = markers.markers.at(0).points;
  ASSERT_FALSE(points.empty());
  EXPECT_NEAR(points.back().x, 3.0, 1e-6);  // the attachment point, rotated into the world
  EXPECT_NEAR(points.back().y, -0.5, 1e-6);
  EXPECT_NEAR(points.back().z, -1.0, 1e-6);
  EXPECT_NEAR(points.front().x, 0.0, 1e-6);  // the spool followed the ship
  EXPECT_NEAR(points.front().y, 1.0, 1e-6);
  EXPECT_NEAR(points.front().z, 0.0, 1e-6);
}

/// The executable `name` in the directory of this test binary.
std::string siblingExecutable(const std::string& name)
{
  char path[4096];
  const ssize_t length = ::readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (length <= 0)
  {
    return name;
  }
  const std::string self(path, static_cast<std::size_t>(length));
  return self.substr(0, self.rfind('/') + 1) + name;
}

// A bad or contradictory parameter stops the node at start, before it advertises anything, naming the
// parameter.
TEST(TetherNodeStartup, BadParameterStopsTheNodeWithAMessage)
{
  const std::array<std::pair<const char*, const char*>, 9> cases = {{
      {"_iterations:=0", "iterations = 0"},
      {"_drag:=lots", "parameter 'drag': wrong type"},
      {"_pose_source:=gps", "pose_source = 'gps'"},
      // contradictory: each value in range, together impossible
      {"_segment_length:=5.0 _cable_length:=2.0", "segment_length = 5: must not exceed cable_length = 2"},
      {"_overload_policy:=panic", "overload_policy = 'panic'"},
      {"_tethers:=a", "parameter 'tethers': expected a non-empty list of names"},
      // a spool on another tether's vehicle (a TMS): only among several, on a dynamic vehicle that has a start
      {"_spool_on:=umbilical", "parameter spool_on = 'umbilical': a spool rides on another tether: list both"},
      {"(spool_outlet_offset set below)", "parameter spool_outlet_offset: only with spool_on"},
      // (tethers [a, b] set below)
      {"_b/spool_on:=a",
       "parameter b/spool_on = 'a': its vehicle must be dynamic (vehicle_model: dynamic) with a vehicle_start"},
  }};
  for (auto [assignment, expected] : cases)
  {
    // Lists cannot be given as command-line assignments: set on the master instead.
    if (std::string(assignment) == "_b/spool_on:=a")
    {
      ros::NodeHandle().setParam("/bad_tether_node/tethers", std::vector<std::string>{"a", "b"});
    }
    if (std::string(assignment) == "(spool_outlet_offset set below)")
    {
      ros::NodeHandle().setParam("/bad_tether_node/spool_outlet_offset", std::vector<double>{0.0, 0.0, -1.0});
      assignment = "";
    }
    // The tether_node built beside this test (rosrun would be ambiguous with a second, sanitizer build).
    const std::string command =
        siblingExecutable("tether_node") + " __name:=bad_tether_node " + assignment + " 2>&1; echo exit=$?";
    std::FILE* pipe = ::popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr)
    {
      output += buffer;
    }
    ::pclose(pipe);
    EXPECT_NE(output.find(expected), std::string::npos) << output;
    EXPECT_NE(output.find("exit=1"), std::string::npos) << output;
    ros::NodeHandle nh;
    nh.deleteParam("/bad_tether_node");  // the next case starts from defaults again
  }
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "tether_node_tf_test");
  ros::NodeHandle nh;  // starts the node's connection before the tests run
  return RUN_ALL_TESTS();
}
