// tether_node: simulates an ROV's tether beside the vehicle stack (see README, "Nodes"). With a private
// parameter `tethers: [a, b, ...]` it simulates several tethers in one process and one World, each
// configured under ~a/, ~b/, ... on top of the parameters they share in ~ (see WorldNode).
#include <ros/ros.h>

#include <cstdio>

#include "rov_tether/ros/world_node.hpp"

int main(int argc, char** argv)
{
  // Line-buffered stdout: ROS_INFO lines then appear as they are logged when stdout is a pipe (roslaunch
  // output="screen" under a pipe, a log collector), not in one block at exit.
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);
  ros::init(argc, argv, "tether_node");
  // Kept alive past a failed start: destroying the last NodeHandle shuts ROS (and its logging) down.
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  try
  {
    rov_tether::ros_layer::WorldNode node(nh, private_nh);
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("tether_node: %s", e.what());
    return 1;
  }
  return 0;
}
