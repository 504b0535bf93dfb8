// tether_node: simulates an ROV's tether beside the vehicle stack (see README, "Nodes").
#include <ros/ros.h>

#include "rov_tether/ros/tether_node.hpp"

int main(int argc, char** argv)
{
  ros::init(argc, argv, "tether_node");
  try
  {
    rov_tether::ros_layer::TetherNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("tether_node: %s", e.what());
    return 1;
  }
  return 0;
}
