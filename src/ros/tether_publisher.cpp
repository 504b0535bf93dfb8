#include "rov_tether/ros/tether_publisher.hpp"

#include <algorithm>

#include "rov_tether/ros/vehicle_io.hpp"

namespace rov_tether::ros_layer
{
namespace
{

/// Index of the contact points in ~markers, after toMarkers' four, of the vehicle's box after them, and of the
/// first of the sections' and attachments' markers (toMaterialMarkers).
constexpr std::size_t kContactMarker = 4;
constexpr std::size_t kVehicleMarker = 5;
constexpr std::size_t kMaterialMarkers = 6;

}  // namespace

void buildMarkers(const Tether& tether, const std::vector<double>& tensions, const ContactRecord& contacts,
                  const Eigen::Isometry3d* vehicle, const Eigen::Vector3d& vehicle_size, const MarkerOptions& options,
                  visualization_msgs::MarkerArray* markers)
{
  const ros::Time stamp(std::max(tether.time(), 0.0));
  toMarkers(tether, tensions, stamp, options, markers);
  markers->markers.resize(std::max<std::size_t>(markers->markers.size(), kVehicleMarker + 1));
  toContactMarker(contacts, stamp, options, &markers->markers[kContactMarker]);
  toVehicleMarker(vehicle != nullptr ? *vehicle : Eigen::Isometry3d::Identity(), vehicle_size, vehicle != nullptr,
                  stamp, options.frame_id, &markers->markers[kVehicleMarker]);
  toMaterialMarkers(tether, stamp, options, kMaterialMarkers, markers);
}

const TetherState& StateBuilder::state(const Tether& tether, std::uint32_t resets)
{
  tether.computeSegmentTensions(tensions_);
  const double physics_time = tether.time();
  const double elapsed = physics_time - last_state_physics_;
  const double deployed = tether.deployedLength();
  const double winch_speed = last_state_physics_ > 0.0 && elapsed > 0.0 ? (deployed - last_deployed_) / elapsed : 0.0;
  last_deployed_ = deployed;
  last_state_physics_ = physics_time;
  stamp_ = ros::Time(std::max(physics_time, 0.0));  // the state is of the physics' time
  toStateMessage(tether, tensions_, stamp_, frame_id_, winch_speed, resets, &msg_);
  return msg_;
}

geometry_msgs::WrenchStamped StateBuilder::wrench(const Tether& tether, const Eigen::Isometry3d& vehicle) const
{
  return toWrench(tether.vehicleForce(), vehicle, attachment_offset_, stamp_, frame_id_);
}

geometry_msgs::WrenchStamped StateBuilder::vehicleWrench(const Tether& tether, const Eigen::Isometry3d& vehicle) const
{
  return toVehicleWrench(tether.vehicleForce(), vehicle, attachment_offset_, stamp_, vehicle_frame_);
}

void StateBuilder::restart(const Tether& tether)
{
  last_state_physics_ = 0.0;
  last_deployed_ = tether.deployedLength();
}

TetherPublisher::TetherPublisher(ros::NodeHandle& private_nh, const NodeOptions& options,
                                 const Eigen::Vector3d& vehicle_size)
    : options_(options),
      vehicle_size_(vehicle_size),
      builder_(options.world_frame, options.rov_frame, options.attachment_offset)
{
  state_pub_ = private_nh.advertise<TetherState>("state", 10);
  wrench_pub_ = private_nh.advertise<geometry_msgs::WrenchStamped>("wrench", 10);
  vehicle_wrench_pub_ = private_nh.advertise<geometry_msgs::WrenchStamped>("wrench_vehicle", 10);
  // A simulator takes the latest; 100 covers half a second of steps at 200 Hz for a subscriber that wants all.
  coupling_pub_ = private_nh.advertise<TetherCoupling>("coupling", 100);
  if (!options.spool_outlet_frame.empty() || !options.cable_end_frame.empty())
  {
    tf_pub_ = private_nh.advertise<tf2_msgs::TFMessage>("/tf", 10);
  }
  marker_pub_ = private_nh.advertise<visualization_msgs::MarkerArray>("markers", 2);
  // The colour legend: latched, drawn once (its scale is a node option, fixed while the node runs).
  legend_pub_ = private_nh.advertise<sensor_msgs::Image>("legend", 1, true);
  MarkerOptions legend_options;
  legend_options.tension_full_scale = options.tension_full_scale;
  legend_options.stripe_segments = options.stripe_segments;
  sensor_msgs::Image legend;
  toLegendImage(legend_options, &legend);
  legend.header.stamp = ros::Time::now();
  legend_pub_.publish(legend);
}

void TetherPublisher::publishState(const Tether& tether, std::uint32_t resets, const Eigen::Isometry3d& vehicle)
{
  state_pub_.publish(builder_.state(tether, resets));
  wrench_pub_.publish(builder_.wrench(tether, vehicle));
  if (vehicle_wrench_pub_.getNumSubscribers() > 0)
  {
    vehicle_wrench_pub_.publish(builder_.vehicleWrench(tether, vehicle));
  }
  if (tf_pub_ && tf_pub_.getNumSubscribers() > 0)
  {
    toTransforms(tether, ros::Time(std::max(tether.time(), 0.0)), options_.world_frame, options_.spool_outlet_frame,
                 options_.cable_end_frame, &transforms_);
    tf_pub_.publish(transforms_);
  }
}

namespace
{

/// Why `tether` cannot give ~coupling, or "" when it can.
std::string whyNoCoupling(const Tether& tether)
{
  if (tether.params().solver != SolverType::kDirect)
  {
    return "it needs solver: direct (this tether runs " + toString(tether.params().solver) + "): set solver: direct";
  }
  if (tether.vehicleDynamic())
  {
    return "the vehicle is dynamic, its tether coupled inside the step: ~coupling is for a kinematic vehicle "
           "end driven by an external simulator's poses";
  }
  return "";
}

}  // namespace

bool TetherPublisher::couplingWanted(const Tether& tether) const
{
  return coupling_pub_.getNumSubscribers() > 0 && whyNoCoupling(tether).empty();
}

void TetherPublisher::publishCoupling(Tether& tether, double horizon)
{
  if (!tether.vehicleAttached())
  {
    return;  // no pose yet (diagnostics say so): nothing pulls anything
  }
  // The simulator's state runs the physics' delay ahead of the step (interpolation_delay, or more when poses
  // come sparse or late): K is the chain's answer over that time.
  const Status status = tether.vehicleEndLinearisation(&linearisation_, horizon);
  if (!status.ok)
  {
    if (coupling_log_.due())
    {
      ROS_WARN("tether_node: %s not published: %s", coupling_pub_.getTopic().c_str(), status.message.c_str());
    }
    return;
  }
  toCouplingMessage(linearisation_, tether.vehicleForce(), options_.world_frame, &coupling_);
  coupling_pub_.publish(coupling_);
}

void TetherPublisher::explainMissingCoupling(const Tether& tether)
{
  const std::string why = coupling_pub_.getNumSubscribers() > 0 ? whyNoCoupling(tether) : "";
  if (why.empty())
  {
    coupling_explained_ = false;
  }
  else if (!coupling_explained_)
  {
    ROS_WARN("tether_node: %s is subscribed but nothing is published: %s", coupling_pub_.getTopic().c_str(),
             why.c_str());
    coupling_explained_ = true;
  }
}

void TetherPublisher::restart(const Tether& tether)
{
  builder_.restart(tether);
  next_marker_time_ = ros::Time();
}

double TetherPublisher::publishMarkers(const Tether& tether, const ContactRecord& contacts, const ros::Time& now,
                                       double rate, const Eigen::Isometry3d* vehicle)
{
  const ros::Duration period(1.0 / rate);
  if (marker_pub_.getNumSubscribers() == 0)
  {
    return 0.0;  // markers cost nothing when nobody looks
  }
  if (!next_marker_time_.isZero() && now < next_marker_time_ && next_marker_time_ - now <= period)
  {
    return 0.0;
  }
  const ros::WallTime start = ros::WallTime::now();
  // A fixed schedule (next += period) keeps the average rate exact on the physics timer's grid.
  const bool behind =
      next_marker_time_.isZero() || now - next_marker_time_ > period || next_marker_time_ - now > period;
  next_marker_time_ = behind ? now + period : next_marker_time_ + period;
  tether.computeSegmentTensions(tensions_);
  MarkerOptions marker_options;
  marker_options.frame_id = options_.world_frame;
  marker_options.line_width = options_.marker_line_width;
  marker_options.tension_full_scale = options_.tension_full_scale;
  marker_options.stripe_segments = options_.stripe_segments;
  buildMarkers(tether, tensions_, contacts, vehicle, vehicle_size_, marker_options, &markers_);
  marker_pub_.publish(markers_);  // serialised here for every remote subscriber: part of the cost
  return (ros::WallTime::now() - start).toSec();
}

}  // namespace rov_tether::ros_layer
