// tether_node: simulates an ROV's tether beside the vehicle stack (see README, "Nodes"). With a private
// parameter `tethers: [a, b, ...]` it simulates several tethers in one process, each configured under
// ~a/, ~b/, ... on top of the parameters they share in ~.
#include <ros/ros.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "rov_tether/ros/tether_node.hpp"

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
    std::vector<std::unique_ptr<rov_tether::ros_layer::TetherNode>> tethers;
    XmlRpc::XmlRpcValue names;
    if (private_nh.getParam("tethers", names))
    {
      if (names.getType() != XmlRpc::XmlRpcValue::TypeArray || names.size() == 0)
      {
        throw std::runtime_error("parameter 'tethers': expected a non-empty list of names");
      }
      XmlRpc::XmlRpcValue shared;
      private_nh.getParam(private_nh.getNamespace(), shared);
      for (int i = 0; i < names.size(); ++i)
      {
        if (names[i].getType() != XmlRpc::XmlRpcValue::TypeString || static_cast<std::string>(names[i]).empty())
        {
          throw std::runtime_error("parameter 'tethers': entry " + std::to_string(i) + " is not a name");
        }
        const std::string name = names[i];
        tethers.push_back(
            std::make_unique<rov_tether::ros_layer::TetherNode>(nh, ros::NodeHandle(private_nh, name), shared, name));
      }
      ROS_INFO("tether_node: %zu tethers in one process", tethers.size());
    }
    else
    {
      tethers.push_back(std::make_unique<rov_tether::ros_layer::TetherNode>(nh, private_nh));
    }
    ros::spin();
  }
  catch (const std::exception& e)
  {
    ROS_FATAL("tether_node: %s", e.what());
    return 1;
  }
  return 0;
}
