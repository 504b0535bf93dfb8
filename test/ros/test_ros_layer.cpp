// The ROS layer without a master: converters, colours, service answers, parameter loading.
#include <gtest/gtest.h>
#include <tf2_ros/buffer.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "../test_helpers.hpp"
#include "rov_tether/camera/camera_model.hpp"
#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/ros/camera_config.hpp"
#include "rov_tether/ros/converters.hpp"
#include "rov_tether/ros/log_throttle.hpp"
#include "rov_tether/ros/markers.hpp"
#include "rov_tether/ros/obstacle_config.hpp"
#include "rov_tether/ros/param_loader.hpp"
#include "rov_tether/ros/reconfigure.hpp"
#include "rov_tether/ros/tether_publisher.hpp"
#include "rov_tether/ros/vehicle_history.hpp"
#include "rov_tether/ros/world_report.hpp"
#include "rov_tether/ros/xmlrpc_yaml.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"
#include "rov_tether/scenario/world_spec.hpp"
#include "rov_tether/spec/yaml_read.hpp"
#include "yaml_xmlrpc.hpp"

namespace rov_tether::ros_layer
{
using test::loadYaml;

namespace
{

/// buildWorld's warnings (a vehicle out of its cable's reach), which the tests here that build a world do not check
/// (Runner.APathStartingOutOfTheTethersReachIsSaid does).
std::vector<std::string> world_warnings;

Tether heavyTether()
{
  TetherParams params;
  params.noise = 0.0;
  params.weight_in_water = 1.0;
  params.winch_mode = WinchMode::kLocked;
  params.initial_deployed_length = 3.0;
  Tether sim(params, Position::Zero(), Position(2.0, 0.0, 0.0));
  EXPECT_TRUE(test::succeeded(sim.advance(10.0)));
  return sim;
}

// Each tether's warnings are throttled by throttles of its own (LogThrottle): ROS_WARN_THROTTLE's throttle belongs to
// the line of code, so with several tethers in one node the first tether's message hid the others' for the period.
// Two owners are each due at the same time; one is due again only a period later (at exactly the period too), at once
// when the clock goes back (a replay started over), and once while the clock stands at 0 (no /clock yet).
TEST(LogThrottle, EachOwnerIsDueOncePerPeriodOfItsOwn)
{
  LogThrottle first(1.0), second(1.0);
  EXPECT_TRUE(first.due(ros::Time(10.0)));
  EXPECT_TRUE(second.due(ros::Time(10.0))) << "another tether's message is not hidden by the first's";
  EXPECT_FALSE(first.due(ros::Time(10.5)));
  EXPECT_TRUE(first.due(ros::Time(11.0)));
  EXPECT_FALSE(second.due(ros::Time(10.9)));
  EXPECT_TRUE(first.due(ros::Time(3.0))) << "the clock went back";
  EXPECT_FALSE(first.due(ros::Time(3.5)));
  LogThrottle waiting(1.0);
  EXPECT_TRUE(waiting.due(ros::Time(0.0)));
  EXPECT_FALSE(waiting.due(ros::Time(0.0))) << "a clock standing at 0 is due once, not at every call";
  EXPECT_TRUE(waiting.due(ros::Time(1.0)));
}

TEST(Colours, TensionScaleRunsFromBlueToRedAndCompressionIsGrey)
{
  auto near = [](const std_msgs::ColorRGBA& c, double r, double g, double b)
  { return std::abs(c.r - r) < 1e-6 && std::abs(c.g - g) < 1e-6 && std::abs(c.b - b) < 1e-6 && c.a == 1.0f; };
  EXPECT_TRUE(near(tensionColor(0.0, 50.0, false), 0.3, 0.55, 1));  // light blue
  EXPECT_TRUE(near(tensionColor(12.5, 50.0, false), 0, 1, 1));      // cyan
  EXPECT_TRUE(near(tensionColor(25.0, 50.0, false), 0, 1, 0));      // green
  EXPECT_TRUE(near(tensionColor(37.5, 50.0, false), 1, 1, 0));      // yellow
  EXPECT_TRUE(near(tensionColor(50.0, 50.0, false), 1, 0, 0));      // red
  EXPECT_TRUE(near(tensionColor(500.0, 50.0, false), 1, 0, 0));     // saturated
  EXPECT_TRUE(near(tensionColor(-1.0, 50.0, false), 0.55, 0.55, 0.55));
  EXPECT_TRUE(near(tensionColor(std::nan(""), 50.0, false), 0.55, 0.55, 0.55));
  EXPECT_TRUE(near(tensionColor(50.0, 50.0, true), 1, 0.4, 0.4));  // a stripe is lighter
}

/// WCAG 2.1 relative luminance of an sRGB colour, components in [0, 1] (docs/references.md).
double luminance(double r, double g, double b)
{
  const auto linear = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  return 0.2126 * linear(r) + 0.7152 * linear(g) + 0.0722 * linear(b);
}

/// WCAG 2.1 contrast ratio (L1 + 0.05) / (L2 + 0.05) of two luminances, the lighter first: 1 to 21.
double contrast(double a, double b) { return (std::max(a, b) + 0.05) / (std::min(a, b) + 0.05); }

// The cable must be visible in rviz at every tension, stripes included: a contrast ratio of at least 3
// (WCAG 2.1's minimum for graphics, docs/references.md) against rviz's own default background (48, 48,
// 48) and the one config/tether.rviz sets. The old scale started at pure blue with darker stripes:
// 1.5 against rviz's grey, 1.2 for its stripes.
TEST(Colours, EveryColourStandsOutOnRvizBackgrounds)
{
  std::ifstream rviz(std::string(ROV_TETHER_SOURCE_DIR) + "/config/tether.rviz");
  std::string line, shipped;
  while (std::getline(rviz, line))
  {
    if (line.find("Background Color:") != std::string::npos)
    {
      shipped = line.substr(line.find(':') + 1);
    }
  }
  int r = 0, g = 0, b = 0;
  ASSERT_EQ(std::sscanf(shipped.c_str(), " %d; %d; %d", &r, &g, &b), 3) << "no background in config/tether.rviz";
  const double backgrounds[] = {luminance(48 / 255.0, 48 / 255.0, 48 / 255.0),
                                luminance(r / 255.0, g / 255.0, b / 255.0)};
  double worst = 21.0;
  for (double tension = -5.0; tension <= 60.0; tension += 0.25)
  {
    for (const bool stripe : {false, true})
    {
      const std_msgs::ColorRGBA c = tensionColor(tension, 50.0, stripe);
      for (const double background : backgrounds)
      {
        worst = std::min(worst, contrast(luminance(c.r, c.g, c.b), background));
      }
    }
  }
  std::printf("[ measured ] cable colours on rviz's backgrounds: lowest contrast ratio %.2f (minimum 3)\n", worst);
  EXPECT_GE(worst, 3.0);
}

// With pose_source topic nothing else may put world_frame into tf, and rviz then warns that its fixed
// frame does not exist; the node publishes the spool outlet and the cable's vehicle end under it.
// The ranges the node publishes for rqt_reconfigure are the table's, and a refused change's WARN names each
// field asked with the value that runs instead (issue 26, item 6).
TEST(Converters, ConfigBoundsAreTheTableRangesAndDifferencesNameAskedAndUsed)
{
  const TetherConfig low = configBounds(false);
  const TetherConfig high = configBounds(true);
  EXPECT_EQ(low.iterations, 1);
  EXPECT_EQ(high.iterations, 1000);
  EXPECT_EQ(high.noise, 1.0);
  EXPECT_EQ(low.drag, 0.0);
  const TetherConfig used = paramsToConfig(TetherParams{});
  TetherConfig asked = used;
  asked.iterations = 0;
  asked.drag = 7.0;
  // In the table's order (the .cfg is generated from it).
  EXPECT_EQ(configDifferences(asked, used), "iterations: asked 0, used 10; drag: asked 7.0, used 0.9");
  EXPECT_EQ(configDifferences(used, used), "");
  // The server clamps a request before the node's callback sees it: to the .cfg's (open) ranges, so what
  // was asked arrives as asked and the node can refuse it by name.
  asked.__clamp__();
  EXPECT_EQ(asked.iterations, 0);
  EXPECT_EQ(asked.drag, 7.0);
}

TEST(Converters, TransformsPlaceTheSpoolOutletAndTheCableEnd)
{
  const Tether sim = heavyTether();
  tf2_msgs::TFMessage message;
  toTransforms(sim, ros::Time(3.0), "world", "tether_spool", "tether_end", &message);
  ASSERT_EQ(message.transforms.size(), 2u);
  const auto& spool = message.transforms[0];
  const auto& end = message.transforms[1];
  EXPECT_EQ(spool.header.frame_id, "world");
  EXPECT_EQ(spool.child_frame_id, "tether_spool");
  EXPECT_EQ(end.child_frame_id, "tether_end");
  EXPECT_EQ(end.header.stamp, ros::Time(3.0));
  EXPECT_EQ(spool.transform.translation.x, sim.particle(0).x());
  EXPECT_NEAR(end.transform.translation.x, 2.0, 1e-12);  // heavyTether's vehicle at (2, 0, 0)
  EXPECT_EQ(end.transform.rotation.w, 1.0);
  toTransforms(sim, ros::Time(3.0), "world", "", "tether_end", &message);
  ASSERT_EQ(message.transforms.size(), 1u) << "an empty name publishes no frame";
  EXPECT_EQ(message.transforms[0].child_frame_id, "tether_end");
}

TEST(Converters, StateMessageCarriesTheSimulation)
{
  const Tether sim = heavyTether();
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  TetherState msg;
  toStateMessage(sim, tensions, ros::Time(12.5), "world", 0.25, 3, &msg);
  const TetherSummary summary = sim.summary();
  EXPECT_EQ(msg.header.stamp, ros::Time(12.5));
  EXPECT_EQ(msg.header.frame_id, "world");
  EXPECT_DOUBLE_EQ(msg.deployed_length, 3.0);
  EXPECT_EQ(msg.cable_length, 10.0);
  ASSERT_EQ(msg.segment_tension.size(), 30u);
  EXPECT_DOUBLE_EQ(msg.tension_spool, summary.tension_spool);
  EXPECT_DOUBLE_EQ(msg.tension_vehicle, summary.tension_vehicle);
  EXPECT_DOUBLE_EQ(msg.max_tension, summary.max_tension);
  EXPECT_EQ(msg.max_tension_segment, summary.max_tension_segment);
  EXPECT_GT(msg.max_tension, 1.0);  // a heavy cable hangs in tension
  // The end forces, world frame: the cable pulls both ends down (a heavy cable hanging between them).
  EXPECT_EQ(Force(msg.spool_force.x, msg.spool_force.y, msg.spool_force.z), summary.spool_force);
  EXPECT_EQ(Force(msg.vehicle_force.x, msg.vehicle_force.y, msg.vehicle_force.z), summary.vehicle_force);
  EXPECT_LT(msg.spool_force.z, 0.0);
  EXPECT_LT(msg.vehicle_force.z, 0.0);
  EXPECT_NEAR(msg.residual_stretch, summary.mean_strain, 1e-12);
  EXPECT_EQ(msg.winch_mode, "locked");
  EXPECT_EQ(msg.winch_speed, 0.25);
  EXPECT_TRUE(std::isnan(msg.target_length));
  EXPECT_EQ(msg.solver, "direct");
  EXPECT_EQ(msg.iterations, 10u);
  EXPECT_EQ(msg.resets, 3u);
  EXPECT_TRUE(msg.vehicle_attached);
}

TEST(Converters, MarkersDrawTheCableColouredByTensionWithStripes)
{
  const Tether sim = heavyTether();
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  visualization_msgs::MarkerArray markers;
  MarkerOptions options;
  options.tension_full_scale = 5.0;
  toMarkers(sim, tensions, ros::Time(3.0), options, &markers);
  ASSERT_EQ(markers.markers.size(), 4u);
  const auto& cable = markers.markers[0];
  EXPECT_EQ(cable.type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_EQ(cable.header.frame_id, "world");
  ASSERT_EQ(cable.points.size(), 60u);
  ASSERT_EQ(cable.colors.size(), 60u);
  EXPECT_NEAR(cable.points.front().x, 0.0, 1e-12);  // starts at the spool
  EXPECT_NEAR(cable.points.back().x, 2.0, 1e-12);   // ends at the vehicle
  const std::size_t first = sim.state().first;
  for (std::size_t k = 0; k < 30; ++k)
  {
    const bool stripe = ((first + k) / 5) % 2 == 1;
    const auto expected = tensionColor(tensions[k], 5.0, stripe);
    EXPECT_EQ(cable.colors[2 * k].r, expected.r) << k;
    EXPECT_EQ(cable.colors[2 * k + 1].g, expected.g) << k;
  }
  EXPECT_EQ(markers.markers[1].type, visualization_msgs::Marker::CYLINDER);
  EXPECT_EQ(markers.markers[2].action, visualization_msgs::Marker::ADD);
  EXPECT_NE(markers.markers[3].text.find("3.00 m out"), std::string::npos);

  // Reused storage: a shorter cable redraws without stale points; a detached vehicle hides its sphere.
  Tether free_end(TetherParams{}, Position::Zero());
  std::vector<double> none;
  free_end.computeSegmentTensions(none);
  toMarkers(free_end, none, ros::Time(4.0), options, &markers);
  EXPECT_EQ(markers.markers[0].points.size(), 40u);
  EXPECT_EQ(markers.markers[2].action, visualization_msgs::Marker::DELETE);
}

// A cable of sections with attachments (issue 22) draws each section in its own colour over the tension
// colours, and each attachment as a sphere where its material is, as big as a sphere of water weighing its
// net buoyancy (a float yellow, a clump weight grey); one still on the drum is hidden.
TEST(Converters, MarkersDrawSectionsAndAttachments)
{
  TetherParams params;
  params.noise = 0.0;
  params.winch_mode = WinchMode::kLocked;
  params.initial_deployed_length = 3.0;
  params.sections = {{1.0, {{"weight_in_water", 2.0}}}, {}};
  CableAttachment float_on;
  float_on.name = "float";
  float_on.arc_length_from_vehicle = 1.5;
  float_on.net_buoyancy = 4.0 / 3.0 * 3.14159265358979 * 0.05 * 0.05 * 0.05 * params.water_density * 9.81;
  CableAttachment clump = float_on;
  clump.name = "clump";
  clump.arc_length_from_vehicle = 5.0;  // on the drum while 3 m are out
  clump.net_buoyancy = -20.0;
  clump.mass = 2.5;  // at least its 20 N in water over g: no body weighs more in water than in air
  params.attachments = {float_on, clump};
  Tether sim(params, Position::Zero(), Position(2.0, 0.0, 0.0));
  ASSERT_TRUE(test::succeeded(sim.advance(1.0)));
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  visualization_msgs::MarkerArray markers;
  toMarkers(sim, tensions, ros::Time(1.0), MarkerOptions{}, &markers);
  ASSERT_EQ(markers.markers.size(), 4u);  // the cable's own; the node puts its contacts and vehicle at 4 and 5
  toMaterialMarkers(sim, ros::Time(1.0), MarkerOptions{}, 4, &markers);
  ASSERT_EQ(markers.markers.size(), 7u);
  const auto& sections = markers.markers[4];
  EXPECT_EQ(sections.ns, "tether_sections");
  EXPECT_EQ(sections.action, visualization_msgs::Marker::ADD);
  ASSERT_EQ(sections.points.size(), 60u);  // 30 deployed segments, from the vehicle end
  EXPECT_NEAR(sections.points.front().x, 2.0, 1e-12);
  const auto vehicle_colour = sections.colors.front(), spool_colour = sections.colors.back();
  EXPECT_NE(vehicle_colour.g, spool_colour.g);
  for (std::size_t k = 0; k < 30; ++k)  // the first 10 segments from the vehicle are the first section's
  {
    EXPECT_EQ(sections.colors[2 * k].g, k < 10 ? vehicle_colour.g : spool_colour.g) << k;
  }
  const auto& sphere = markers.markers[5];
  EXPECT_EQ(sphere.action, visualization_msgs::Marker::ADD);
  EXPECT_NEAR(sphere.scale.x, 0.1, 1e-9);                       // a 5 cm radius sphere of water weighs its buoyancy
  const std::size_t at = sim.deployedParticleCount() - 1 - 15;  // 1.5 m from the vehicle on 0.1 m segments
  EXPECT_NEAR(sphere.pose.position.x, sim.particle(at).x(), 1e-12);
  EXPECT_NEAR(sphere.pose.position.z, sim.particle(at).z(), 1e-12);
  EXPECT_GT(sphere.color.g, 0.8f);                                           // yellow
  EXPECT_EQ(markers.markers[6].action, visualization_msgs::Marker::DELETE);  // on the drum

  // As the node publishes them, after its contact points and vehicle box: every marker its own (ns, id).
  visualization_msgs::MarkerArray node;
  const Eigen::Isometry3d vehicle = Eigen::Isometry3d::Identity();
  buildMarkers(sim, tensions, ContactRecord{}, &vehicle, Eigen::Vector3d::Ones(), MarkerOptions{}, &node);
  ASSERT_EQ(node.markers.size(), 9u);
  std::set<std::pair<std::string, int>> ids;
  for (const auto& marker : node.markers)
  {
    EXPECT_TRUE(ids.insert({marker.ns, marker.id}).second) << marker.ns << " " << marker.id;
  }
  EXPECT_EQ(node.markers[6].ns, "tether_sections");
  EXPECT_EQ(node.markers[7].ns, "tether_attachments");
  EXPECT_EQ(node.markers[7].action, visualization_msgs::Marker::ADD);
}

// The legend a user reads the cable's colours by (issue 26, item 16), an image rviz shows beside its 3D view:
// every colour of the scale as a swatch in exactly the colour the cable gets at that tension (tensionColor,
// at 8 bits), the compression grey, and a stripe half plain, half lighter; on config/tether.rviz's background.
// Each swatch is kLegendSwatch x 12 px of its colour; the text is antialiased white, so a colour of the
// scale appears nowhere else in such a block.
TEST(Converters, LegendImageShowsEveryColourOfTheScaleTheGreyAndTheStripes)
{
  MarkerOptions options;
  options.tension_full_scale = 40.0;
  options.stripe_segments = 7;
  sensor_msgs::Image image;
  toLegendImage(options, &image);
  ASSERT_EQ(image.encoding, "bgr8");
  ASSERT_EQ(image.width, static_cast<std::uint32_t>(kLegendWidth));
  ASSERT_EQ(image.height, static_cast<std::uint32_t>(kLegendHeight));
  ASSERT_EQ(image.step, image.width * 3);
  ASSERT_EQ(image.data.size(), image.step * image.height);
  const auto pixels = [&](const std_msgs::ColorRGBA& c)
  {
    const auto byte = [](float v) { return static_cast<std::uint8_t>(std::lround(255.0 * v)); };
    std::size_t n = 0;
    for (std::size_t p = 0; p + 2 < image.data.size(); p += 3)
    {
      n += image.data[p] == byte(c.b) && image.data[p + 1] == byte(c.g) && image.data[p + 2] == byte(c.r);
    }
    return n;
  };
  const std::size_t swatch = kLegendSwatch * 12;
  for (const double tension : {0.0, 10.0, 20.0, 30.0, 40.0})
  {
    // 0 N's colour is also the plain half of the stripe swatch.
    EXPECT_EQ(pixels(tensionColor(tension, 40.0, false)), tension == 0.0 ? swatch + swatch / 2 : swatch) << tension;
  }
  EXPECT_EQ(pixels(tensionColor(-1.0, 40.0, false)), swatch);    // the compression grey
  EXPECT_EQ(pixels(tensionColor(0.0, 40.0, true)), swatch / 2);  // the lighter stripe
  EXPECT_EQ(image.data[0], 64);  // blue, green, red of config/tether.rviz's background (12, 38, 64)
  EXPECT_EQ(image.data[1], 38);
  EXPECT_EQ(image.data[2], 12);
  // Reused storage: a second legend of another scale has the same size and that scale's red.
  options.tension_full_scale = 10.0;
  toLegendImage(options, &image);
  EXPECT_EQ(image.data.size(), image.step * image.height);
  EXPECT_EQ(pixels(tensionColor(10.0, 10.0, false)), swatch);
}

TEST(Converters, WrenchIsThePullOnTheVehicle)
{
  const Tether sim = heavyTether();
  // The vehicle origin 0.5 m above the attachment: attachment_offset (0, 0, -0.5).
  const Eigen::Isometry3d vehicle(Eigen::Translation3d(2.0, 0.0, 0.5));
  const Force force = sim.vehicleForce();
  const geometry_msgs::WrenchStamped wrench =
      toWrench(force, vehicle, Eigen::Vector3d(0.0, 0.0, -0.5), ros::Time(1.0), "world");
  EXPECT_EQ(wrench.header.frame_id, "world");
  EXPECT_DOUBLE_EQ(wrench.wrench.force.x, force.x());
  EXPECT_DOUBLE_EQ(wrench.wrench.force.z, force.z());
  EXPECT_LT(force.z(), -0.5);  // the hanging cable pulls the vehicle down
  EXPECT_LT(force.x(), 0.0);   // and towards the spool
  // Torque about the vehicle origin: r = (0, 0, -0.5), tau = r x F.
  EXPECT_NEAR(wrench.wrench.torque.y, -0.5 * force.x(), 1e-12);
}

// The pull is of the physics' time, behind the latest pose; its lever arm and the vehicle frame it is
// given in are the vehicle's at that time. A vehicle turning at 90 deg/s, the attachment 0.5 m behind
// it: at the physics' time it faced 45 degrees, not the latest pose's 90.
TEST(Converters, WrenchesUseTheVehiclePoseAtTheForcesTimeInBothFrames)
{
  VehicleHistory history;
  const auto yawed = [](double degrees)
  { return Eigen::Isometry3d(Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ())); };
  history.add(10.0, yawed(0.0));
  history.add(11.0, yawed(90.0));
  const Eigen::Isometry3d at_force = history.at(10.5);
  EXPECT_TRUE(at_force.isApprox(yawed(45.0), 1e-12));
  const Force pull(3.0, -1.0, 0.5);
  const Eigen::Vector3d offset(-0.5, 0.0, 0.0);
  const auto world = toWrench(pull, at_force, offset, ros::Time(10.5), "world");
  const Eigen::Vector3d lever = yawed(45.0).rotation() * offset;  // (-0.354, -0.354, 0)
  const Eigen::Vector3d torque = lever.cross(pull);
  EXPECT_NEAR(world.wrench.torque.x, torque.x(), 1e-12);
  EXPECT_NEAR(world.wrench.torque.y, torque.y(), 1e-12);
  EXPECT_NEAR(world.wrench.torque.z, torque.z(), 1e-12);
  const Eigen::Vector3d latest_torque = (yawed(90.0).rotation() * offset).cross(pull);
  EXPECT_GT((torque - latest_torque).norm(), 0.1) << "the latest pose's lever arm is another torque";

  const auto own = toVehicleWrench(pull, at_force, offset, ros::Time(10.5), "rov");
  EXPECT_EQ(own.header.frame_id, "rov");
  const Eigen::Vector3d f(own.wrench.force.x, own.wrench.force.y, own.wrench.force.z);
  const Eigen::Vector3d tau(own.wrench.torque.x, own.wrench.torque.y, own.wrench.torque.z);
  EXPECT_TRUE((yawed(45.0).rotation() * f).isApprox(pull, 1e-12)) << "the same force, in the vehicle frame";
  EXPECT_TRUE((yawed(45.0).rotation() * tau).isApprox(torque, 1e-12)) << "the same torque, in the vehicle frame";
  EXPECT_TRUE(tau.isApprox(offset.cross(f), 1e-12));
  EXPECT_NEAR(f.x(), pull.dot(yawed(45.0).rotation().col(0)), 1e-12) << "x is the vehicle's forward axis";
}

// ~coupling carries the linearisation as given, K and C row-major (an asymmetric K tells rows from columns),
// stamped with its physics time in the world frame, F0 the pull ~wrench gives.
TEST(Converters, CouplingMessageCarriesTheLinearisationRowMajorAtItsPhysicsTime)
{
  EndLinearisation linearisation;
  linearisation.time = 12.345;
  linearisation.position = Position(10.0, -2.0, -3.0);
  linearisation.velocity = Velocity(0.5, 0.25, -0.125);
  linearisation.force = Force(-40.0, 1.0, 2.0);
  linearisation.stiffness << -1e4, 1.0, 2.0, 3.0, -40.0, 4.0, 5.0, 6.0, -40.5;
  linearisation.damping << -1.0, -2.0, -3.0, -4.0, -5.0, -6.0, -7.0, -8.0, -9.0;
  linearisation.taut = true;
  const Force pull(-39.0, 0.5, 1.5);
  TetherCoupling msg;
  toCouplingMessage(linearisation, pull, "world", &msg);
  EXPECT_EQ(msg.header.stamp, ros::Time(12.345));
  EXPECT_EQ(msg.header.frame_id, "world");
  EXPECT_EQ(Eigen::Vector3d(msg.force.x, msg.force.y, msg.force.z), pull);
  EXPECT_EQ(Eigen::Vector3d(msg.position.x, msg.position.y, msg.position.z), linearisation.position);
  EXPECT_EQ(Eigen::Vector3d(msg.velocity.x, msg.velocity.y, msg.velocity.z), linearisation.velocity);
  EXPECT_EQ(msg.stiffness[1], 1.0) << "row 0, column 1";
  EXPECT_EQ(msg.stiffness[3], 3.0) << "row 1, column 0";
  EXPECT_EQ(msg.damping[5], -6.0) << "row 1, column 2";
  for (int k = 0; k < 9; ++k)
  {
    EXPECT_EQ(msg.stiffness[k], linearisation.stiffness(k / 3, k % 3)) << k;
    EXPECT_EQ(msg.damping[k], linearisation.damping(k / 3, k % 3)) << k;
  }
  EXPECT_TRUE(msg.taut);
}

// A cable cannot push: when the vehicle drives into the cable faster than it can give way, the end
// segment is compressed and PBD's bilateral constraint carries a negative tension, which would push the
// vehicle away. The force (weightless cable) and so the wrench then carry nothing (EndForces has the core's
// side, with a weight in water).
TEST(Converters, ACompressedEndSegmentPushesNothing)
{
  TetherParams params;
  params.noise = 0.0;
  params.solver = SolverType::kPbd;  // bilateral: it carries the compression (direct's segments cannot)
  params.winch_mode = WinchMode::kLocked;
  params.initial_deployed_length = 3.0;
  Tether sim(params, Position::Zero(), Position(3.0, 0.0, 0.0));  // straight and taut along x
  for (int k = 1; k <= 20; ++k)
  {
    ASSERT_TRUE(test::succeeded(
        sim.addVehicleSample(0.01 * k, Position(3.0 - 0.05 * k, 0.0, 0.0))));  // 5 m/s back along the cable
  }
  bool compressed = false;
  for (int k = 0; k < 20 && !compressed; ++k)
  {
    sim.step();
    compressed = sim.summary().tension_vehicle < -0.1;
  }
  ASSERT_TRUE(compressed) << "the end segment never carried compression";
  EXPECT_EQ(sim.vehicleForce(), Force::Zero());
  const auto wrench = toWrench(sim.vehicleForce(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(-0.5, 0.0, 0.0),
                               ros::Time(1.0), "world");
  EXPECT_EQ(wrench.wrench.force.x, 0.0);
  EXPECT_EQ(wrench.wrench.torque.z, 0.0);
}

TEST(Converters, GetTensionAnswersBySegmentOrArcLengthAndRefusesTheRest)
{
  const Tether sim = heavyTether();
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  GetTension::Request request;
  GetTension::Response response;
  request.segment = 4;
  request.arc_length_from_vehicle = -1.0;
  answerGetTension(sim, tensions, request, &response);
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_EQ(response.segment, 4u);
  EXPECT_EQ(response.tension, tensions[4]);
  EXPECT_EQ(response.tension_spool, tensions.front());
  EXPECT_EQ(response.tension_vehicle, tensions.back());

  request.segment = -1;
  request.arc_length_from_vehicle = 0.25;  // third segment from the vehicle
  answerGetTension(sim, tensions, request, &response);
  ASSERT_TRUE(response.success) << response.message;
  EXPECT_EQ(response.segment, 27u);

  for (auto [segment, arc] : std::vector<std::pair<int, double>>{{30, -1.0}, {-1, 3.5}, {-1, -1.0}, {2, 1.0}})
  {
    request.segment = segment;
    request.arc_length_from_vehicle = arc;
    answerGetTension(sim, tensions, request, &response);
    EXPECT_FALSE(response.success) << segment << " " << arc;
    EXPECT_FALSE(response.message.empty());
  }
}

// `rosservice call /tether_node/get_tension "{}"` sends both fields 0, which was refused as ambiguous:
// the empty request answers the vehicle end (arc length 0 from the vehicle), with both ends and the maximum.
TEST(Converters, EmptyGetTensionRequestAnswersTheVehicleEnd)
{
  TetherParams params;
  params.weight_in_water = 1.0;
  Tether sim(params, Position::Zero(), Position(1.5, 0.0, -0.5));
  ASSERT_TRUE(test::succeeded(sim.advance(1.0)));
  std::vector<double> tensions;
  sim.computeSegmentTensions(tensions);
  GetTension::Request request;  // all zero
  GetTension::Response response;
  answerGetTension(sim, tensions, request, &response);
  EXPECT_TRUE(response.success) << response.message;
  EXPECT_EQ(response.segment, tensions.size() - 1);
  EXPECT_EQ(response.tension, tensions.back());
  EXPECT_EQ(response.tension_vehicle, tensions.back());
  EXPECT_EQ(response.tension_spool, tensions.front());
  EXPECT_EQ(response.max_tension, *std::max_element(tensions.begin(), tensions.end()));
  ASSERT_GT(tensions.size(), 1u);  // so the vehicle end is not segment 0
  // Explicit requests are unchanged: segment 0 is the spool's, arc length 0 (segment -1) the vehicle's.
  request.segment = 0;
  request.arc_length_from_vehicle = -1.0;
  answerGetTension(sim, tensions, request, &response);
  EXPECT_TRUE(response.success);
  EXPECT_EQ(response.segment, 0u);
  request.segment = -1;
  request.arc_length_from_vehicle = 0.0;
  answerGetTension(sim, tensions, request, &response);
  EXPECT_TRUE(response.success);
  EXPECT_EQ(response.segment, tensions.size() - 1);
}

// dynamic_reconfigure fields map to the model parameters by name, both ways, through the core's table.
TEST(Reconfigure, ConfigAndParamsMapByName)
{
  TetherParams params;
  params.drag = 0.7;
  params.iterations = 25;
  params.bending = false;
  params.solver = SolverType::kPbdSequential;
  params.winch_mode = WinchMode::kSpeed;
  params.winch_speed = -0.4;
  const TetherConfig config = paramsToConfig(params);
  EXPECT_EQ(config.drag, 0.7);
  EXPECT_EQ(config.iterations, 25);
  EXPECT_FALSE(config.bending);
  EXPECT_EQ(config.solver, "pbd_sequential");
  EXPECT_EQ(config.winch_mode, "speed");
  TetherParams back;
  ASSERT_EQ(configToParams(config, &back), "");
  int fields = 0;
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    EXPECT_EQ(getParameter(back, description->name), getParameter(params, description->name)) << description->name;
    ++fields;
  }
  EXPECT_GE(fields, 15);  // drag, iterations, noise and every other live parameter

  TetherConfig bad = config;
  bad.winch_mode = "turbo";
  EXPECT_NE(configToParams(bad, &back).find("winch_mode"), std::string::npos);
}

// `iterations: auto` and `segment_length: auto` (which the README recommends) stopped the node at start:
// the config was built from the unresolved values ("auto" is not a number). It shows what auto chose.
TEST(Reconfigure, AutoValuesShowAsWhatTheyChose)
{
  TetherParams params;
  params.iterations_auto = true;
  params.segment_length_auto = true;
  params.weight_in_water = 1.0;
  TetherConfig config;
  ASSERT_NO_THROW(config = paramsToConfig(params));
  EXPECT_EQ(config.iterations, params.resolved().iterations);
  EXPECT_GE(config.iterations, 1);
}

// A live change keeps what the user asked apart from what it resolved to: the request starts from the asked
// parameters, and only the fields that differ from what the server shows are set. Before, the node started
// from the resolved values, so the first live change of anything froze `iterations: auto` to its number.
// pbd's auto count is ceil(L a h^2 / (2 tol dL^2)), a = weight_in_water / mass_per_length (resolved()): with the
// defaults (L 10 m, h 0.005 s, dL 0.1 m, tol 0.01) 12.5 -> 13 at 1 N/m and 62.5 -> 63 at 5 N/m.
TEST(Reconfigure, AutoIterationsStayAutoThroughALiveChange)
{
  TetherParams asked;
  asked.solver = SolverType::kPbd;
  asked.weight_in_water = 1.0;
  asked.iterations_auto = true;
  ASSERT_EQ(asked.resolved().iterations, 13);
  TetherConfig config = paramsToConfig(asked);
  config.weight_in_water = 5.0;  // the one change: a heavier cable needs more sweeps
  ASSERT_EQ(applyConfigChanges(config, &asked), "");
  EXPECT_TRUE(asked.iterations_auto);
  EXPECT_EQ(asked.weight_in_water, 5.0);
  EXPECT_EQ(asked.resolved().iterations, 63);  // resolved again, not frozen at 13

  // A change of solver keeps auto too: direct's auto is its Newton limit.
  config = paramsToConfig(asked);
  config.solver = "direct";
  ASSERT_EQ(applyConfigChanges(config, &asked), "");
  EXPECT_TRUE(asked.iterations_auto);
  EXPECT_EQ(asked.resolved().iterations, kDirectIterations);

  // A number for iterations ends auto; the next change keeps that number.
  config = paramsToConfig(asked);
  config.iterations = 40;
  ASSERT_EQ(applyConfigChanges(config, &asked), "");
  EXPECT_FALSE(asked.iterations_auto);
  EXPECT_EQ(asked.iterations, 40);
  config = paramsToConfig(asked);
  config.solver = "pbd";
  ASSERT_EQ(applyConfigChanges(config, &asked), "");
  EXPECT_EQ(asked.resolved().iterations, 40);
}

// `iterations: auto` chooses lumped_mass's substeps (half its critical step): a live substeps would be
// overridden at once, so it is refused with the reason, and nothing changes. `segment_length: auto` is not
// live (it rebuilds the cable), so no request can reach it.
TEST(Reconfigure, ALiveChangeAutoWouldOverrideIsRefused)
{
  TetherParams asked;
  asked.solver = SolverType::kLumpedMass;
  asked.iterations_auto = true;
  const int chosen = asked.resolved().substeps;
  ASSERT_GT(chosen, 1);
  const TetherParams before = asked;
  TetherConfig config = paramsToConfig(asked);
  EXPECT_EQ(config.substeps, chosen);
  config.substeps = chosen + 5;
  const std::string error = applyConfigChanges(config, &asked);
  EXPECT_NE(error.find("substeps = " + std::to_string(chosen + 5)), std::string::npos) << error;
  EXPECT_NE(error.find("iterations: auto"), std::string::npos) << error;
  for (const std::string& name : parameterNames())
  {
    EXPECT_TRUE(test::sameParamValue(getParameter(asked, name), getParameter(before, name))) << name;
  }
  // With a number for iterations in the same request, substeps is the user's.
  config.iterations = 20;  // not the 10 shown (auto leaves lumped_mass's iterations as they were)
  ASSERT_EQ(applyConfigChanges(config, &asked), "");
  EXPECT_FALSE(asked.iterations_auto);
  EXPECT_EQ(asked.resolved().substeps, chosen + 5);
  // A bad field is named, and nothing changes.
  config = paramsToConfig(asked);
  config.drag = 7.0;
  EXPECT_NE(applyConfigChanges(config, &asked).find("drag"), std::string::npos);
  EXPECT_EQ(asked.drag, before.drag);
}

// The dynamic_reconfigure server clamps the whole set on every request to the .cfg's ranges, which are
// open (the node checks against the table itself), so no valid value is changed by a request that did not
// touch it. Every live numeric
// parameter at each end of its range (just inside an open end) survives a round trip through the config
// and its clamping while the user changes something else.
TEST(Reconfigure, ClampingNeverChangesAValidValue)
{
  int checked = 0;
  for (const ParameterInfo& row : parameterInfo())
  {
    if (!row.live || std::isnan(row.min))
    {
      continue;  // choices and flags
    }
    const bool integer = row.type.rfind("int", 0) == 0;
    for (double bound : {row.min_open ? row.min + 1e-9 * (row.max - row.min) : row.min,
                         row.max_open ? row.max - 1e-9 * (row.max - row.min) : row.max})
    {
      TetherParams params;
      params.max_winch_speed = 20.0;  // so winch_speed may span its whole range [-20, 20]
      params.segment_length = 2.0;    // so noise may span its whole range (a sub-step's share <= segment / 10)
      params.min_deployed_length = 2.0;
      params.axial_stiffness = 1e7;  // so weight_in_water may span its whole range (w L < EA: 1e4 N/m x 10 m)
      ASSERT_EQ(
          setParameter(params, row.name, integer ? ParamValue(static_cast<std::int64_t>(bound)) : ParamValue(bound)),
          "");
      ASSERT_TRUE(params.validate().empty()) << row.name << " = " << bound;
      TetherConfig config = paramsToConfig(params);
      const std::string touched = row.name == "drag" ? "noise" : "drag";
      (touched == "drag" ? config.drag : config.noise) = 0.3;  // the one change the user asked for
      config.__clamp__();
      TetherParams after = params;
      ASSERT_EQ(configToParams(config, &after), "");
      for (const std::string& name : parameterNames())
      {
        if (name != touched)
        {
          EXPECT_TRUE(test::sameParamValue(getParameter(after, name), getParameter(params, name)))
              << name << " changed when " << row.name << " = " << bound;
        }
      }
      ++checked;
    }
  }
  EXPECT_GE(checked, 40);  // two ends of every live numeric parameter
}

TEST(ParameterServer, ModelParametersLoadThroughTheCoreLoader)
{
  XmlRpc::XmlRpcValue dict;
  dict["iterations"] = 4;
  dict["drag"] = 0.8;
  dict["bending"] = false;
  dict["winch_mode"] = std::string("locked");
  dict["world_frame"] = std::string("odom");  // a node option, not a model parameter
  TetherParams params;
  ASSERT_EQ(loadTetherParams(dict, &params), "");
  EXPECT_EQ(params.iterations, 4);
  EXPECT_EQ(params.drag, 0.8);
  EXPECT_FALSE(params.bending);
  EXPECT_EQ(params.winch_mode, WinchMode::kLocked);

  XmlRpc::XmlRpcValue bad;
  bad["iterations"] = 0;
  bad["drag"] = std::string("lots");
  TetherParams unchanged;
  const std::string error = loadTetherParams(bad, &unchanged);
  EXPECT_NE(error.find("parameter 'drag': wrong type"), std::string::npos) << error;
  EXPECT_EQ(unchanged.iterations, 10);  // nothing applied on error
  bad["drag"] = 0.5;
  EXPECT_NE(loadTetherParams(bad, &unchanged).find("iterations = 0"), std::string::npos);
  XmlRpc::XmlRpcValue list;
  list.setSize(1);
  list[0] = 1.0;
  bad["drag"] = list;
  EXPECT_NE(loadTetherParams(bad, &unchanged).find("'drag': wrong type (a list)"), std::string::npos);
  list[0] = std::string("x");
  bad["drag"] = list;
  EXPECT_NE(loadTetherParams(bad, &unchanged).find("drag: expected a list of numbers"), std::string::npos);
  // A list parameter: the current [m/s].
  XmlRpc::XmlRpcValue good;
  XmlRpc::XmlRpcValue current;
  current.setSize(3);
  current[0] = 0.5, current[1] = 0, current[2] = -0.1;
  good["current"] = current;
  ASSERT_EQ(loadTetherParams(good, &unchanged), "");
  EXPECT_EQ(unchanged.current[0], 0.5);
  EXPECT_EQ(unchanged.current[2], -0.1);
  XmlRpc::XmlRpcValue short_list;
  short_list.setSize(2);
  short_list[0] = 0.5, short_list[1] = 0.0;
  good["current"] = short_list;
  EXPECT_NE(loadTetherParams(good, &unchanged).find("expected a list of 3 numbers"), std::string::npos);
}

// One reader of model parameters (spec::readTetherParams) for the node and the runner: the same values on
// the parameter server (XmlRpc, converted to YAML) and in a scenario's `params:` give the same parameters,
// whatever their type (integer, number, bool, string, list, NaN); a bad value is refused with the same
// message by both.
TEST(ParameterServer, TheNodeAndTheRunnerReadParametersWithOneReader)
{
  const std::string good =
      "{iterations: 4, drag: 0.8, bending: false, winch_mode: locked, solver: direct, "
      "current: [0.5, 0, -0.1], seabed_z: -12.5, payout_threshold: 1}";
  TetherParams node;
  ASSERT_EQ(loadTetherParams(rov_tether::test::toXmlRpc(YAML::Load(good)), &node), "");
  Scenario scenario;
  ASSERT_EQ(parseScenario("spool: [0, 0, 0]\nduration: 1\nparams: " + good, &scenario), "");
  for (const auto& name : parameterNames())
  {
    EXPECT_TRUE(test::sameParamValue(getParameter(node, name), getParameter(scenario.params, name))) << name;
  }
  EXPECT_EQ(node.iterations, 4);
  EXPECT_EQ(node.current[0], 0.5);
  EXPECT_EQ(node.seabed_z, -12.5);
  // NaN (no seabed) from the parameter server, as config/default.yaml's `.nan` loads.
  XmlRpc::XmlRpcValue nan;
  nan["seabed_z"] = std::nan("");
  node.seabed_z = 0.0;
  ASSERT_EQ(loadTetherParams(nan, &node), "");
  EXPECT_TRUE(std::isnan(node.seabed_z));
  const std::string bad[] = {"{iterations: 0}",   "{drag: lots}",   "{drag: [1]}", "{current: [1, a, 2]}",
                             "{current: [1, 2]}", "{solver: fast}", "{bending: 3}"};
  for (const auto& entry : bad)
  {
    TetherParams unchanged;
    const std::string from_node = loadTetherParams(rov_tether::test::toXmlRpc(YAML::Load(entry)), &unchanged);
    const std::string from_runner = parseScenario("spool: [0, 0, 0]\nduration: 1\nparams: " + entry, &scenario);
    EXPECT_FALSE(from_node.empty()) << entry;
    // The same message, the node's "parameter 'drag': why" (or "drag = 0: why") under the scenario's "params.",
    // where it reads "params.drag: why".
    const std::string quoted = "parameter '";
    const std::size_t end = from_node.rfind(quoted, 0) == 0 ? from_node.find("':") : std::string::npos;
    const std::string expected =
        end == std::string::npos
            ? "params." + from_node
            : "params." + from_node.substr(quoted.size(), end - quoted.size()) + from_node.substr(end + 1);
    EXPECT_EQ(expected, from_runner) << entry;
    EXPECT_EQ(unchanged.iterations, TetherParams{}.iterations) << entry;  // nothing applied on error
  }
}

// A cable's sections and attachments (issue 22) from the parameter server (lists of maps) read as the runner
// reads them from a scenario's params, and are no unknown keys; a bad one is refused with the same message.
TEST(ParameterServer, SectionsAndAttachmentsReadAsTheRunnerReadsThem)
{
  const std::string good =
      "{segment_length: 0.5, sections: [{length: 4, weight_in_water: 1.5}, {axial_stiffness: 2e4}], "
      "attachments: [{name: float, arc_length_from_vehicle: 3, mass: 0.4, net_buoyancy: 6}]}";
  const XmlRpc::XmlRpcValue dict = rov_tether::test::toXmlRpc(YAML::Load(good));
  TetherParams node;
  ASSERT_EQ(loadTetherParams(dict, &node), "");
  EXPECT_EQ(unknownParameters(dict), "");
  Scenario scenario;
  ASSERT_EQ(parseScenario("spool: [0, 0, 0]\nduration: 1\nparams: " + good, &scenario), "");
  ASSERT_EQ(node.sections.size(), 2u);
  EXPECT_EQ(node.sections, scenario.params.sections);
  EXPECT_EQ(node.attachments, scenario.params.attachments);
  EXPECT_EQ(node.attachments.at(0).net_buoyancy, 6.0);
  const std::string bad = "{attachments: [{name: float, arc_length_from_vehicle: -3}]}";
  TetherParams unchanged;
  const std::string from_node = loadTetherParams(rov_tether::test::toXmlRpc(YAML::Load(bad)), &unchanged);
  const std::string from_runner = parseScenario("spool: [0, 0, 0]\nduration: 1\nparams: " + bad, &scenario);
  EXPECT_NE(from_node.find("attachments[0] 'float': arc_length_from_vehicle = -3 m"), std::string::npos) << from_node;
  EXPECT_EQ("params." + from_node, from_runner);
  EXPECT_TRUE(unchanged.attachments.empty());
}

TEST(ParameterServer, NodeOptionsAreCheckedAndTyposReported)
{
  XmlRpc::XmlRpcValue dict;
  dict["pose_source"] = std::string("tf");
  dict["physics_rate"] = 100;
  XmlRpc::XmlRpcValue offset;
  offset.setSize(3);
  offset[0] = 0.5;
  offset[1] = 0;
  offset[2] = -0.1;
  dict["attachment_offset"] = offset;
  NodeOptions options;
  ASSERT_EQ(loadNodeOptions(dict, &options), "");
  EXPECT_EQ(options.pose_source, "tf");
  EXPECT_EQ(options.physics_rate, 100.0);
  EXPECT_EQ(options.attachment_offset, Eigen::Vector3d(0.5, 0.0, -0.1));

  dict["pose_source"] = std::string("gps");
  dict["physics_rate"] = -5.0;
  XmlRpc::XmlRpcValue short_offset;  // setSize only grows an array: build a new one
  short_offset.setSize(2);
  short_offset[0] = 0.5;
  short_offset[1] = 0.0;
  dict["attachment_offset"] = short_offset;
  NodeOptions unchanged;
  const std::string error = loadNodeOptions(dict, &unchanged);
  EXPECT_NE(error.find("pose_source = 'gps'"), std::string::npos) << error;
  EXPECT_NE(error.find("physics_rate"), std::string::npos) << error;
  EXPECT_NE(error.find("attachment_offset"), std::string::npos) << error;
  EXPECT_EQ(unchanged.pose_source, "topic");

  XmlRpc::XmlRpcValue typos;
  typos["iteratons"] = 3;
  typos["drag"] = 0.9;
  typos["world_frame"] = std::string("map");
  EXPECT_EQ(unknownParameters(typos), "iteratons (did you mean iterations?)");
  typos["world_fram"] = std::string("map");  // a node option's typo is matched against the node options too
  EXPECT_EQ(unknownParameters(typos), "iteratons (did you mean iterations?), world_fram (did you mean world_frame?)");
}

// A tether's map that `tethers` does not list (a typo in the list or in the map's name, or one left out) makes no
// tether: it is named as such among the unknown keys, which the node warns of, in a file of several tethers (whose
// shared keys went unchecked: the map, and a typo beside it, were ignored without a word) as with one; a listed map
// is known.
TEST(ParameterServer, ATethersMapThatTethersDoesNotListIsReported)
{
  const XmlRpc::XmlRpcValue several = rov_tether::test::toXmlRpc(
      YAML::Load("{tethers: [t0, t1], t0: {pose_topic: rov0/pose}, t1: {pose_topic: rov1/pose}, "
                 "t2: {pose_topic: rov2/pose}, iteratons: 3}"));
  EXPECT_EQ(unknownParameters(several),
            "iteratons (did you mean iterations?), t2 (a map of parameters that `tethers` does not list: add it there "
            "to simulate it as a tether)");
  const XmlRpc::XmlRpcValue one = rov_tether::test::toXmlRpc(YAML::Load("{cable_length: 20, t0: {pose_topic: a}}"));
  EXPECT_EQ(unknownParameters(one),
            "t0 (a map of parameters that `tethers` does not list: there is no `tethers` list to simulate it as a "
            "tether)");
}

// The node's counts (stripe_segments, min_iterations) take whole numbers, written 3 or 3.0; a fraction is
// refused with the option's name, not truncated to the count below it (which a user would not see).
TEST(ParameterServer, WholeNumberOptionsRefuseFractions)
{
  XmlRpc::XmlRpcValue dict;
  dict["stripe_segments"] = 3;
  dict["min_iterations"] = 4.0;
  NodeOptions options;
  ASSERT_EQ(loadNodeOptions(dict, &options), "");
  EXPECT_EQ(options.stripe_segments, 3);
  EXPECT_EQ(options.min_iterations, 4);

  for (const char* name : {"stripe_segments", "min_iterations"})
  {
    for (const double bad : {2.7, 0.0, 1001.0})
    {
      XmlRpc::XmlRpcValue one;
      one[name] = bad;
      NodeOptions unchanged;
      const std::string error = loadNodeOptions(one, &unchanged);
      EXPECT_NE(error.find(std::string(name) + ": expected a whole number in [1, 1000]"), std::string::npos)
          << name << " = " << bad << ": " << error;
      EXPECT_EQ(unchanged.stripe_segments, NodeOptions().stripe_segments);
      EXPECT_EQ(unchanged.min_iterations, NodeOptions().min_iterations);
    }
  }
}

// A key given twice in a YAML file the launch loaded: roslaunch keeps the last without a word, so the shipped
// launch files list the files in param_files and the node reads each again (checkParamFiles) and refuses a
// repeated key, naming the file, the key and both lines. "" (an optional file not given) is skipped, a clean
// file passes, a relative path is read from $PWD (where roslaunch read it; the node runs in ROS_HOME), a file
// the node cannot read (roslaunch read it on another machine, say) is only warned of, and a param_files that
// is no list of strings is refused when the options are read.
TEST(ParameterServer, AKeyGivenTwiceInALoadedFileIsRefused)
{
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("rov_tether_param_files_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string clean = (dir / "clean.yaml").string(), twice = (dir / "twice.yaml").string();
  std::ofstream(clean) << "iterations: 3\ndrag: 0.9\n";
  std::ofstream(twice) << "iterations: 3\ndrag: 0.9\niterations: 700\n";
  XmlRpc::XmlRpcValue files;
  files[0] = clean;
  files[1] = std::string();
  XmlRpc::XmlRpcValue dict;
  dict["param_files"] = files;
  NodeOptions options;
  ASSERT_EQ(loadNodeOptions(dict, &options), "");
  EXPECT_EQ(options.param_files, (std::vector<std::string>{clean, ""}));
  EXPECT_EQ(checkParamFiles(options.param_files), "");

  EXPECT_EQ(checkParamFiles({clean, "", twice}),
            "param_files: " + twice + ": duplicate key 'iterations' (lines 1 and 3): give each key once");
  const char* pwd = std::getenv("PWD");
  const std::string saved = pwd != nullptr ? pwd : "";
  setenv("PWD", dir.c_str(), 1);
  EXPECT_EQ(checkParamFiles({"twice.yaml"}),
            "param_files: " + twice + ": duplicate key 'iterations' (lines 1 and 3): give each key once");
  EXPECT_EQ(checkParamFiles({"missing.yaml", "/nowhere/missing.yaml"}), "");  // warned of, not refused
  pwd != nullptr ? setenv("PWD", saved.c_str(), 1) : unsetenv("PWD");

  dict["param_files"] = clean;  // one path, not a list
  NodeOptions refused;
  EXPECT_NE(loadNodeOptions(dict, &refused).find("param_files: expected a list of strings"), std::string::npos);
  std::ofstream(twice) << "a: [1, 2\n";  // YAML that does not parse
  EXPECT_NE(checkParamFiles({twice}).find(twice + ": YAML error"), std::string::npos);
  EXPECT_NE(rov_tether::spec::checkYamlFile((dir / "missing.yaml").string()).find("cannot read"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// Every shipped configuration file loads through the node's loaders, with no unknown key, and
// default.yaml gives exactly the core's defaults.
TEST(ParameterServer, EveryShippedConfigFileLoads)
{
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(ROV_TETHER_SOURCE_DIR) + "/config"))
  {
    if (entry.path().extension() != ".yaml")
    {
      continue;
    }
    const XmlRpc::XmlRpcValue dict = loadYaml("config/" + entry.path().filename().string());
    TetherParams params;
    NodeOptions options;
    EXPECT_EQ(loadTetherParams(dict, &params), "") << entry.path();
    EXPECT_EQ(loadNodeOptions(dict, &options), "") << entry.path();
    EXPECT_EQ(unknownParameters(dict), "") << entry.path();
    WorldOptions world_options;
    EXPECT_EQ(loadWorldOptions(dict, &world_options), "") << entry.path();
    if (dict.hasMember("cameras"))
    {
      std::vector<CameraConfig> cameras;
      EXPECT_EQ(loadCameraConfigs(dict["cameras"], {}, &cameras), "") << entry.path();
      for (const auto& camera : cameras)
      {
        EXPECT_NO_THROW(camera::CameraModel(camera.intrinsics)) << entry.path() << ": " << camera.name;
      }
    }
    ++files;
  }
  EXPECT_GE(files, 3);

  TetherParams from_file;
  from_file.iterations = 77;
  ASSERT_EQ(loadTetherParams(loadYaml("config/default.yaml"), &from_file), "");
  for (const auto& name : parameterNames())
  {
    const ParamValue loaded = getParameter(from_file, name);
    const ParamValue expected = getParameter(TetherParams{}, name);
    const bool both_nan = std::holds_alternative<double>(loaded) && std::isnan(std::get<double>(loaded)) &&
                          std::holds_alternative<double>(expected) && std::isnan(std::get<double>(expected));
    EXPECT_TRUE(both_nan || loaded == expected) << name;  // seabed_z: NaN (no seabed) in both
  }
  NodeOptions node_defaults;
  node_defaults.physics_rate = 1.0;
  node_defaults.solver_residual_warning = 0.5;
  ASSERT_EQ(loadNodeOptions(loadYaml("config/node.yaml"), &node_defaults), "");
  EXPECT_EQ(node_defaults.physics_rate, NodeOptions{}.physics_rate);
  EXPECT_EQ(node_defaults.solver_residual_warning, NodeOptions{}.solver_residual_warning);
  EXPECT_EQ(node_defaults.world_frame, NodeOptions{}.world_frame);
}

// The `cameras` list and CameraInfo: each bad entry is refused naming it.
TEST(CameraConfig, BadEntriesAndCameraInfosAreNamed)
{
  const auto load = [](const std::string& yaml)
  {
    std::vector<CameraConfig> cameras;
    return loadCameraConfigs(rov_tether::test::toXmlRpc(YAML::Load(yaml)), {"t0"}, &cameras);
  };
  const std::string fixed = "width: 64, height: 48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]";
  EXPECT_EQ(load("[{name: a, frame: f, " + fixed + ", rate: 5}, {name: b, frame: f, info_topic: i, image_topic: c}]"),
            "");
  const std::pair<std::string, std::string> cases[] = {
      {"{name: a}", "cameras: expected a list"},
      {"[{name: a, " + fixed + "}]", "cameras[0].frame: missing"},
      {"[{name: a, frame: f}]", "cameras[0]: give either info_topic or the fixed intrinsics"},
      {"[{name: a, frame: f, info_topic: i, " + fixed + "}]", "give either info_topic or the fixed"},
      {"[{name: a, frame: f, info_topic: i, image_topic: c, rate: 5}]", "cameras[0]: give either image_topic or rate"},
      {"[{name: a, frame: f, info_topic: i, rate: 0}]", "cameras[0].rate = 0: must be in (0, 1000] Hz"},
      {"[{name: a, frame: f, width: 64, height: 48, K: [50, 0, 31.5]}]", "cameras[0].K: expected a list of 9"},
      {"[{name: a, frame: f, " + fixed + ", D: [1, 2]}]", "cameras[0].D: expected a list of 5"},
      {"[{name: 2a, frame: f, info_topic: i}]", "cameras[0].name = '2a'"},
      {"[{name: t0, frame: f, info_topic: i}]", "cameras[0].name = 't0': already used by a tether"},
      {"[{name: a, frame: f, info_topic: i, fov: 3}]", "cameras[0]: unknown field 'fov'"},
  };
  for (const auto& [yaml, expected] : cases)
  {
    const std::string error = load(yaml);
    EXPECT_NE(error.find(expected), std::string::npos) << yaml << " gave: " << error;
  }
  sensor_msgs::CameraInfo info;
  info.width = 64;
  info.height = 48;
  info.K = {50, 0, 31.5, 0, 50, 23.5, 0, 0, 1};
  info.distortion_model = "plumb_bob";
  info.D = {-0.1, 0.01, 0, 0, 0};
  camera::CameraIntrinsics intrinsics;
  EXPECT_EQ(intrinsicsFromCameraInfo(info, &intrinsics), "");
  EXPECT_EQ(intrinsics.D, info.D);
  EXPECT_EQ(intrinsics.fx(), 50.0);
  info.distortion_model = "equidistant";
  EXPECT_NE(intrinsicsFromCameraInfo(info, &intrinsics).find("only plumb_bob"), std::string::npos);
  info.distortion_model = "plumb_bob";
  info.binning_x = 2;
  EXPECT_NE(intrinsicsFromCameraInfo(info, &intrinsics).find("binning"), std::string::npos);
  info.binning_x = 0;
  info.K[0] = 0.0;
  EXPECT_NE(intrinsicsFromCameraInfo(info, &intrinsics).find("fx"), std::string::npos);
}

// One reader of cameras (spec::readCameras) for the node and the runner: the same camera described on
// the parameter server (XmlRpc, converted to YAML) and in a scenario file reads the same (name, rate,
// intrinsics); only how it is placed differs (a tf frame on the node, a pose on the vehicle in a scenario).
TEST(CameraConfig, TheNodeAndTheRunnerReadTheSameCamera)
{
  const std::string camera =
      "name: fwd_1, rate: 12.5, width: 640, height: 480, "
      "K: [400.0, 0.0, 319.5, 0.0, 401.0, 239.5, 0.0, 0.0, 1.0], D: [-0.05, 0.01, 0.0, 0.0, 0.0]";
  std::vector<CameraConfig> node;
  ASSERT_EQ(
      loadCameraConfigs(rov_tether::test::toXmlRpc(YAML::Load("[{frame: f, " + camera + "}]")), {"tether"}, &node), "");
  Scenario scenario;
  ASSERT_EQ(
      parseScenario("spool: [0, 0, 0]\nvehicle: [[0, 1, 0, 0]]\nduration: 1\ncameras: [{position: [0.3, 0, 0.1], " +
                        camera + "}]",
                    &scenario),
      "");
  ASSERT_EQ(node.size(), 1u);
  ASSERT_EQ(scenario.cameras.size(), 1u);
  const ScenarioCamera& runner = scenario.cameras[0];
  EXPECT_EQ(node[0].name, "fwd_1");
  EXPECT_EQ(node[0].name, runner.name);
  EXPECT_EQ(node[0].rate, 12.5);
  EXPECT_EQ(node[0].rate, runner.rate);
  EXPECT_EQ(node[0].intrinsics.width, 640);
  EXPECT_EQ(node[0].intrinsics.fy(), 401.0);
  EXPECT_EQ(node[0].intrinsics.D, runner.intrinsics.D);  // as written, not padded to 5
  EXPECT_EQ(node[0].intrinsics, runner.intrinsics);
  EXPECT_EQ(runner.position, Eigen::Vector3d(0.3, 0.0, 0.1));
}

// A bad field of a camera is refused by the node and the runner with the same message, naming the entry,
// the field, the value and what is allowed; one naming rule (a ROS name and a directory name) for both.
TEST(CameraConfig, TheNodeAndTheRunnerRefuseABadCameraAlike)
{
  const std::string intrinsics = "width: 64, height: 48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]";
  const std::pair<std::string, std::string> cases[] = {
      {"name: 2a, " + intrinsics, "cameras[0].name = '2a': expected 1-64 letters, digits or '_', not a digit first"},
      {"name: a-b, " + intrinsics, "cameras[0].name = 'a-b'"},
      {"name: " + std::string(65, 'a') + ", " + intrinsics, "expected 1-64 letters"},
      {"name: a, rate: 0, " + intrinsics, "cameras[0].rate = 0: must be in (0, 1000] Hz"},
      {"name: a, rate: 1001, " + intrinsics, "cameras[0].rate = 1001: must be in (0, 1000] Hz"},
      {"name: a, width: 64.5, height: 48, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]",
       "cameras[0].width = 64.5: must be a whole number in [1, 16384] px"},
      {"name: a, width: 64, height: 0, K: [50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]",
       "cameras[0].height = 0: must be a whole number in [1, 16384] px"},
      {"name: a, width: 64, height: 48", "cameras[0].K: missing"},
      {"name: a, width: 64, height: 48, K: [50, 0, 31.5]", "cameras[0].K: expected a list of 9 numbers"},
      {"name: a, width: 64, height: 48, K: [-50, 0, 31.5, 0, 50, 23.5, 0, 0, 1]", "cameras[0].K: fx = K[0] = -50"},
      {"name: a, D: [1, 2], " + intrinsics, "cameras[0].D: expected a list of 5 plumb_bob coefficients"},
      {"name: a, D: [2000, 0, 0, 0], " + intrinsics, "cameras[0].D[0] = 2000"},
      {"name: a, fov: 3, " + intrinsics, "cameras[0]: unknown field 'fov'"},
  };
  for (const auto& [entry, expected] : cases)
  {
    std::vector<CameraConfig> cameras;
    const std::string node =
        loadCameraConfigs(rov_tether::test::toXmlRpc(YAML::Load("[{frame: f, " + entry + "}]")), {}, &cameras);
    Scenario scenario;
    const std::string runner =
        parseScenario("spool: [0, 0, 0]\nvehicle: [[0, 1, 0, 0]]\nduration: 1\ncameras: [{" + entry + "}]", &scenario);
    EXPECT_NE(node.find(expected), std::string::npos) << entry << " gave: " << node;
    // The same message up to the list of fields an unknown one is told (each path has its own).
    EXPECT_EQ(node.substr(0, node.find(" (expected")), runner.substr(0, runner.find(" (expected"))) << entry;
  }
}

// The mask and depth messages are updated at the pixels that changed only; they must equal full copies.
TEST(CameraConfig, IncrementalImageMessagesEqualFullCopies)
{
  camera::CameraIntrinsics c;
  c.width = 160;
  c.height = 120;
  c.K = {100, 0, 79.5, 0, 100, 59.5, 0, 0, 1};
  const camera::CameraModel model(c);
  camera::TetherRenderer renderer;
  sensor_msgs::Image mask, depth, full;
  std::vector<int> mask_pixels, depth_pixels;
  std_msgs::Header header;
  // A tether sweeping across the view, then gone, then back; then close enough to fill a third of the
  // view (more changed pixels than the per-pixel copy is used for), then back in the distance twice.
  for (int frame = 0; frame < 7; ++frame)
  {
    const bool close = frame == 4;
    std::vector<Position> points;
    for (int i = 0; i <= 20; ++i)
    {
      points.emplace_back(-1.0 + 0.1 * i, close ? 0.0 : -0.3 + 0.1 * frame,
                          frame == 2 ? -2.0 : (close ? 0.5 : 1.5 + 0.05 * i));
    }
    const camera::RenderStats stats =
        renderer.render(model, Eigen::Isometry3d::Identity(), {camera::Tube{&points, close ? 0.1 : 0.03}}, {});
    if (close)
    {
      EXPECT_GT(stats.coverage, 0.25);
    }
    header.seq = frame;
    updateImageMessage(renderer.mask(), renderer.pixels(), &mask_pixels, header, &mask);
    updateImageMessage(renderer.depth(), renderer.pixels(), &depth_pixels, header, &depth);
    toImageMessage(renderer.mask(), header, &full);
    EXPECT_EQ(mask.data, full.data) << "frame " << frame;
    toImageMessage(renderer.depth(), header, &full);
    // Bytewise, so NaN equals NaN.
    EXPECT_EQ(depth.data, full.data) << "frame " << frame;
    EXPECT_EQ(depth.encoding, "32FC1");
    EXPECT_EQ(depth.header.seq, static_cast<std::uint32_t>(frame));
  }
}

// Review of the camera node, item 1: a CameraInfo of up to 16384 x 16384 px passed the per-side check, and
// building its camera took more than 2 GB (rays alone: 8 bytes a pixel); the std::bad_alloc killed the node.
// Now at most 4096 x 4096 pixels are taken, whatever the sides, and the message says the cap, from a
// CameraInfo and from the `cameras` list alike (one check: CameraIntrinsics::validate).
TEST(CameraConfig, ACameraOfMoreThan4096By4096PixelsIsRefused)
{
  sensor_msgs::CameraInfo info;
  info.K = {1000, 0, 0, 0, 1000, 0, 0, 0, 1};
  const auto refusal = [&](std::uint32_t width, std::uint32_t height)
  {
    info.width = width;
    info.height = height;
    info.K[2] = 0.5 * width - 0.5;
    info.K[5] = 0.5 * height - 0.5;
    camera::CameraIntrinsics intrinsics;
    return intrinsicsFromCameraInfo(info, &intrinsics);
  };
  EXPECT_NE(refusal(16384, 16384).find("width x height = 16384 x 16384 = 268435456 px: at most 4096 x 4096"),
            std::string::npos)
      << refusal(16384, 16384);
  EXPECT_NE(refusal(8192, 2049).find("at most 4096 x 4096 = 16777216 px"), std::string::npos) << "one row too many";
  EXPECT_EQ(refusal(4096, 4096), "");
  EXPECT_EQ(refusal(8192, 2048), "") << "as many pixels as 4096 x 4096, in another shape";
  EXPECT_EQ(refusal(16384, 1), "") << "each side is still allowed up to 16384";
  std::vector<CameraConfig> cameras;
  const std::string error = loadCameraConfigs(
      rov_tether::test::toXmlRpc(YAML::Load(
          "[{name: a, frame: f, width: 10000, height: 10000, K: [5000, 0, 4999.5, 0, 5000, 4999.5, 0, 0, 1]}]")),
      {}, &cameras);
  EXPECT_NE(error.find("cameras[0].width x height = 10000 x 10000"), std::string::npos) << error;
}

// Review of the camera node, item 1: only std::invalid_argument was caught around building a camera from a
// CameraInfo, so a std::bad_alloc (or OpenCV's cv::Exception) escaped the callback and ended the node.
// buildCameraModel turns any std::exception into the reason the CameraInfo is refused, and keeps what
// *model held; here the builder fails as memory or OpenCV would.
TEST(CameraConfig, ACameraThatCannotBeBuiltIsRefusedNotThrown)
{
  camera::CameraIntrinsics intrinsics;
  intrinsics.width = 64;
  intrinsics.height = 48;
  intrinsics.K = {50, 0, 31.5, 0, 50, 23.5, 0, 0, 1};
  std::unique_ptr<camera::CameraModel> model;
  std::string error;
  EXPECT_NO_THROW(error = buildCameraModel(intrinsics, &model,
                                           [](const camera::CameraIntrinsics&,
                                              const camera::BuildAbandoned&) -> std::unique_ptr<camera::CameraModel>
                                           { throw std::bad_alloc(); }));
  EXPECT_EQ(error, "building the 64x48 camera ran out of memory");
  EXPECT_EQ(model, nullptr);
  EXPECT_NO_THROW(error = buildCameraModel(intrinsics, &model,
                                           [](const camera::CameraIntrinsics&,
                                              const camera::BuildAbandoned&) -> std::unique_ptr<camera::CameraModel>
                                           { throw std::runtime_error("cv::undistortPoints failed"); }));
  EXPECT_EQ(error, "building the 64x48 camera failed: cv::undistortPoints failed");
  EXPECT_EQ(model, nullptr);
  // Invalid intrinsics are refused naming the field, as before; valid ones are built.
  intrinsics.K[0] = -1.0;
  EXPECT_NE(buildCameraModel(intrinsics, &model).find("fx = K[0] = -1"), std::string::npos);
  EXPECT_EQ(model, nullptr);
  intrinsics.K[0] = 50.0;
  EXPECT_EQ(buildCameraModel(intrinsics, &model), "");
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->width(), 64);
  // Abandoned part-way (the worker's shutdown), CameraModel's constructor stops and the build says so, keeping
  // what *model held.
  camera::CameraModel* kept = model.get();
  intrinsics.width = 32;
  EXPECT_EQ(buildCameraModel(intrinsics, &model, {}, [] { return true; }), camera::CameraBuildAbandoned().what());
  EXPECT_EQ(model.get(), kept);
}

// Review of the camera node, item 4: sensor_msgs/CameraInfo says a roi of the full image (offsets 0, the
// image's width and height) means the same as all zeros, but any roi with a non-zero size was refused
// (camera drivers that fill it in could not be used). It is taken now; a smaller or offset roi and binning
// above 1 are still refused, naming them.
TEST(CameraConfig, ARegionOfInterestOfTheFullImageIsTaken)
{
  sensor_msgs::CameraInfo info;
  info.width = 64;
  info.height = 48;
  info.K = {50, 0, 31.5, 0, 50, 23.5, 0, 0, 1};
  info.roi.width = 64;
  info.roi.height = 48;
  camera::CameraIntrinsics intrinsics;
  EXPECT_EQ(intrinsicsFromCameraInfo(info, &intrinsics), "");
  EXPECT_EQ(intrinsics.width, 64);
  EXPECT_EQ(intrinsics.height, 48);
  info.binning_x = info.binning_y = 1;  // 1 is no binning, as 0
  EXPECT_EQ(intrinsicsFromCameraInfo(info, &intrinsics), "");
  info.roi.width = 32;
  EXPECT_NE(
      intrinsicsFromCameraInfo(info, &intrinsics).find("roi (x_offset, y_offset, width, height) = (0, 0, 32, 48)"),
      std::string::npos);
  info.roi.width = 64;
  info.roi.x_offset = 1;
  EXPECT_NE(intrinsicsFromCameraInfo(info, &intrinsics).find("a region of interest other than the full image"),
            std::string::npos);
  info.roi.x_offset = 0;
  info.binning_y = 2;
  EXPECT_NE(intrinsicsFromCameraInfo(info, &intrinsics).find("binning_y = 2"), std::string::npos);
}

// ---- Obstacles (issue 14): the `obstacles` list, ~obstacles, contact points, ~topology. ----

std::string loadObstacles(const std::string& yaml, WorldOptions* options = nullptr)
{
  WorldOptions scratch;
  return loadWorldOptions(rov_tether::test::toXmlRpc(YAML::Load(yaml)), options ? options : &scratch);
}

// Every entry the list can get wrong is refused naming the entry (index and name) and the field, and the
// options are left as they were; the node refuses to start with this message (WorldNode throws, main logs
// it with ROS_FATAL), as for any bad parameter.
TEST(Obstacles, BadEntriesAreRefusedNamingTheEntryAndTheField)
{
  WorldOptions options;
  ASSERT_EQ(loadObstacles("{tether_contact: false, obstacles: [{name: pillar, type: cylinder, position: [4, 0, -5], "
                          "radius: 0.5, length: 12}, {name: deck, type: plane, orientation: [0, 0.1, 0], "
                          "friction: 0.2, frame: ship}]}",
                          &options),
            "");
  ASSERT_EQ(options.obstacles.size(), 2u);
  EXPECT_FALSE(options.tether_contact);
  EXPECT_EQ(options.obstacles[0].type, ShapeType::Cylinder);
  EXPECT_EQ(options.obstacles[0].position, Position(4.0, 0.0, -5.0));
  EXPECT_EQ(options.obstacles[0].friction, 0.5);  // the default
  EXPECT_EQ(options.obstacles[1].frame, "ship");
  EXPECT_EQ(options.obstacles[1].orientation, Eigen::Vector3d(0.0, 0.1, 0.0));

  const std::pair<std::string, std::string> cases[] = {
      {"{obstacles: {name: a}}", "obstacles: expected a list"},
      {"{obstacles: [3]}", "obstacles[0]: expected a map"},
      {"{obstacles: [{type: sphere, radius: 1}]}", "obstacles[0] name: expected a non-empty string"},
      {"{obstacles: [{name: a, type: cone, radius: 1}]}", "obstacles[0] 'a' type: expected sphere, box"},
      {"{obstacles: [{name: a, type: sphere, radius: 1, colour: red}]}", "obstacles[0] 'a': unknown field 'colour'"},
      {"{obstacles: [{name: a, type: sphere, radius: 1, position: [1, 2]}]}",
       "obstacles[0] 'a' position: expected [x, y, z]"},
      {"{obstacles: [{name: a, type: sphere, radius: one}]}", "obstacles[0] 'a' radius: expected a number"},
      {"{obstacles: [{name: a, type: sphere, radius: 1, frame: 3}]}", "obstacles[0] 'a' frame: expected a string"},
      {"{obstacles: [{name: a, type: sphere, radius: 1}, {name: p, type: cylinder, radius: 0.5}]}",
       "obstacles[1]: obstacle 'p' (cylinder): length must be > 0 m"},
      {"{obstacles: [{name: b, type: box, size: [1, 0, 1]}]}", "obstacles[0]: obstacle 'b' (box): size must be"},
      {"{obstacles: [{name: w, type: mesh}]}", "obstacles[0]: obstacle 'w' (mesh): a mesh needs a file"},
      {"{obstacles: [{name: a, type: sphere, radius: 1, friction: 11}]}",
       "obstacle 'a' (sphere): friction must be in [0, 10]"},
      {"{obstacles: [{name: a, type: sphere, radius: 1}, {name: a, type: sphere, radius: 2}]}",
       "obstacles[1] 'a' name: taken by an earlier obstacle"},
      {"{tether_contact: 1}", "tether_contact: expected true or false"},
  };
  for (const auto& [yaml, expected] : cases)
  {
    WorldOptions unchanged = options;
    const std::string error = loadObstacles(yaml, &unchanged);
    EXPECT_NE(error.find(expected), std::string::npos) << yaml << " gave: " << error;
    EXPECT_EQ(unchanged.obstacles.size(), 2u) << yaml;
  }
  // Every bad entry of a list is reported, not just the first.
  const std::string both = loadObstacles("{obstacles: [{name: a, type: cone}, {name: b, type: sphere}]}");
  EXPECT_NE(both.find("obstacles[0] 'a' type"), std::string::npos) << both;
  EXPECT_NE(both.find("obstacles[1]: obstacle 'b' (sphere): radius must be > 0 m"), std::string::npos) << both;
}

// One reader of obstacles (spec::readObstacles) for the node and the runner: the same entry, through the
// parameter server (XmlRpc, converted to YAML) or in a scenario file, is refused with the same message,
// whatever check it fails. The bounds on coordinates, once only the runner's, and the tether's name, once
// checked apart by the node, hold for both. Only what a scenario cannot have differs (a tf frame, a URI).
TEST(Obstacles, TheNodeAndTheRunnerReadObstaclesWithOneReader)
{
  const std::string entries[] = {
      "3",
      "{type: sphere, radius: 1}",
      "{name: a, type: cone, radius: 1}",
      "{name: a, type: sphere, radius: 1, colour: red}",
      "{name: a, type: sphere, radius: 1, position: [1, 2]}",
      "{name: a, type: sphere, radius: one}",
      "{name: a, type: sphere, radius: '1'}",
      "{name: p, type: cylinder, radius: 0.5}",
      "{name: b, type: box, size: [1, 0, 1]}",
      "{name: w, type: mesh}",
      "{name: a, type: sphere, radius: 1, friction: 11}",
      "{name: a, type: sphere, radius: 1, position: [2e6, 0, 0]}",
      "{name: a, type: sphere, radius: 2e6}",
      "{name: tether, type: sphere, radius: 1}",
  };
  for (const std::string& entry : entries)
  {
    WorldOptions options;
    const std::string node =
        loadWorldOptions(rov_tether::test::toXmlRpc(YAML::Load("{obstacles: [" + entry + "]}")), &options, {"tether"});
    Scenario scenario;
    const std::string runner =
        parseScenario("spool: [0, 0, 0]\nvehicle: [[0, 1, 0, 0]]\nduration: 1\nobstacles: [" + entry + "]", &scenario);
    EXPECT_FALSE(node.empty()) << entry;
    EXPECT_EQ(node.substr(0, node.find(" (")), runner.substr(0, runner.find(" ("))) << entry;
  }
  // A string is never a number, as the parameter server types it.
  WorldOptions options;
  XmlRpc::XmlRpcValue quoted = rov_tether::test::toXmlRpc(YAML::Load("{obstacles: [{name: a, type: sphere}]}"));
  quoted["obstacles"][0]["radius"] = std::string("1");
  EXPECT_NE(loadWorldOptions(quoted, &options).find("obstacles[0] 'a' radius: expected a number"), std::string::npos);
  // The conversion keeps numbers exactly, and types.
  XmlRpc::XmlRpcValue value;
  value["x"] = 0.1;
  value["n"] = 3;
  value["on"] = true;
  value["s"] = std::string("0.5");
  const YAML::Node yaml = toYaml(value);
  EXPECT_EQ(yaml["x"].as<double>(), 0.1);
  EXPECT_EQ(yaml["n"].as<int>(), 3);
  EXPECT_TRUE(yaml["on"].as<bool>());
  EXPECT_EQ(yaml["s"].Tag(), "!");
}

TEST(Obstacles, WarningThresholdsAreCheckedNodeOptions)
{
  NodeOptions options;
  EXPECT_EQ(options.wrap_warning_turns, 0.5);
  EXPECT_EQ(options.snag_ratio, 3.0);
  XmlRpc::XmlRpcValue dict;
  dict["wrap_warning_turns"] = 0.25;
  dict["snag_ratio"] = 2;
  ASSERT_EQ(loadNodeOptions(dict, &options), "");
  EXPECT_EQ(options.wrap_warning_turns, 0.25);
  EXPECT_EQ(options.snag_ratio, 2.0);
  dict["wrap_warning_turns"] = 0.0;
  dict["snag_ratio"] = 1.0;  // a capstan ratio is e^(mu angle) >= 1: every contact would be a snag
  const std::string error = loadNodeOptions(dict, &options);
  EXPECT_NE(error.find("wrap_warning_turns: expected a number in (0, 1e+06]"), std::string::npos) << error;
  EXPECT_NE(error.find("snag_ratio: expected a number in (1, 1e+09]"), std::string::npos) << error;
  EXPECT_EQ(options.wrap_warning_turns, 0.25);  // unchanged
}

TEST(Obstacles, MeshFilesResolveToPathsAndToRvizUris)
{
  std::string error;
  EXPECT_EQ(resolveMeshFile("/data/wreck.stl", &error), "/data/wreck.stl");
  EXPECT_EQ(resolveMeshFile("file:///data/wreck.stl", &error), "/data/wreck.stl");
  EXPECT_EQ(resolveMeshFile("meshes/wreck.stl", &error), "");
  EXPECT_NE(error.find("expected an absolute path, file:///path or package://package/path"), std::string::npos);
  EXPECT_EQ(resolveMeshFile("package://no_such_package_here/wreck.stl", &error), "");
  EXPECT_NE(error.find("no package 'no_such_package_here'"), std::string::npos) << error;
  EXPECT_EQ(meshResourceUri("/data/wreck.stl"), "file:///data/wreck.stl");
  EXPECT_EQ(meshResourceUri("file:///data/wreck.stl"), "file:///data/wreck.stl");
  EXPECT_EQ(meshResourceUri("package://rov_tether/meshes/wreck.stl"), "package://rov_tether/meshes/wreck.stl");
}

/// A mesh as toObstacleMarkers sees one: its spec, pose and bounds (its geometry, assimp and FCL, is
/// mesh_obstacle's, not the markers'). A 2 m cube of bounds about its origin.
class MeshForMarkers : public Obstacle
{
 public:
  using Obstacle::Obstacle;
  Aabb bounds() const override
  {
    Aabb box;
    box.grow(pose_ * Position(-1.0, -1.0, -1.0));
    box.grow(pose_ * Position(1.0, 1.0, 1.0));
    return box;
  }
  bool push(const Position&, const Position&, double, Push*) const override { return false; }
};

TEST(Obstacles, MarkersDrawEveryTypeWhereItIs)
{
  WorldOptions options;
  ASSERT_EQ(loadObstacles("{obstacles: ["
                          "{name: s, type: sphere, position: [1, 2, 3], radius: 0.5},"
                          "{name: b, type: box, position: [0, 0, -1], orientation: [0, 0, 1.5707963267948966], "
                          "size: [1, 2, 3]},"
                          "{name: c, type: cylinder, radius: 0.25, length: 4},"
                          "{name: k, type: capsule, orientation: [1.5707963267948966, 0, 0], radius: 0.1, length: 2},"
                          "{name: p, type: plane, position: [0, 0, -30]},"
                          "{name: m, type: mesh, file: /data/wreck.stl, scale: 0.001, position: [5, 0, -20]}]}",
                          &options),
            "");
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  for (const ObstacleSpec& spec : options.obstacles)
  {
    Status status;
    obstacles.push_back(spec.type == ShapeType::Mesh ? std::make_unique<MeshForMarkers>(spec)
                                                     : makePrimitive(spec, &status));
    ASSERT_TRUE(obstacles.back()) << status.message;
  }
  World world;
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  visualization_msgs::MarkerArray array;
  toObstacleMarkers(world, ros::Time(0), "map", &array);
  std::vector<visualization_msgs::Marker> shapes, names;
  for (const auto& marker : array.markers)
  {
    (marker.ns == "obstacles" ? shapes : names).push_back(marker);
    EXPECT_EQ(marker.header.frame_id, "map");
  }
  using visualization_msgs::Marker;
  ASSERT_EQ(shapes.size(), 8u);  // the capsule is three
  const int types[] = {Marker::SPHERE, Marker::CUBE,   Marker::CYLINDER, Marker::CYLINDER,
                       Marker::SPHERE, Marker::SPHERE, Marker::CUBE,     Marker::MESH_RESOURCE};
  for (std::size_t i = 0; i < shapes.size(); ++i)
  {
    EXPECT_EQ(shapes[i].type, types[i]) << i;
    EXPECT_EQ(shapes[i].id, static_cast<int>(i));  // unique in the namespace
  }
  EXPECT_EQ(shapes[0].scale.x, 1.0);  // a diameter
  EXPECT_EQ(shapes[0].pose.position.z, 3.0);
  EXPECT_EQ(shapes[1].scale.y, 2.0);  // a box's edge lengths, turned by its pose
  EXPECT_NEAR(shapes[1].pose.orientation.z, std::sin(M_PI / 4), 1e-12);
  EXPECT_EQ(shapes[2].scale.x, 0.5);
  EXPECT_EQ(shapes[2].scale.z, 4.0);
  // The capsule along -y (rolled +90 degrees about x): its end spheres at y = -+1.
  EXPECT_NEAR(shapes[4].pose.position.y, 1.0, 1e-12);
  EXPECT_NEAR(shapes[5].pose.position.y, -1.0, 1e-12);
  EXPECT_EQ(shapes[4].scale.x, 0.2);
  // The plane: a thin square just below its surface.
  EXPECT_EQ(shapes[6].scale.x, kPlaneMarkerSize);
  EXPECT_EQ(shapes[6].scale.z, kPlaneMarkerThickness);
  EXPECT_NEAR(shapes[6].pose.position.z, -30.0 - 0.5 * kPlaneMarkerThickness, 1e-12);
  EXPECT_EQ(shapes[7].mesh_resource, "file:///data/wreck.stl");
  EXPECT_EQ(shapes[7].scale.x, 0.001);
  ASSERT_EQ(names.size(), 6u);
  EXPECT_EQ(names[5].text, "m");
  EXPECT_EQ(names[5].type, Marker::TEXT_VIEW_FACING);
  EXPECT_GT(names[0].pose.position.z, 3.5);  // above the sphere's top

  // Moved (as the node does for an obstacle on a frame): drawn where it now is.
  world.setObstaclePose(0, Position(-1.0, 0.0, 0.0), Eigen::Quaterniond::Identity());
  toObstacleMarkers(world, ros::Time(0), "map", &array);
  EXPECT_EQ(array.markers[0].pose.position.x, -1.0);
  EXPECT_EQ(array.markers.size(), 14u);  // rebuilt, not appended
}

TEST(Obstacles, ContactPointsAreDrawnWhereTheCableTouches)
{
  ContactRecord record;
  record.obstacle = {-1, 2, -1, -1};
  record.tether = {-1, -1, 0, -1};
  record.point = {Position(9, 9, 9), Position(1, 0, 0), Position(2, 0, 0), Position(9, 9, 9)};
  MarkerOptions options;
  options.line_width = 0.05;
  visualization_msgs::Marker marker;
  toContactMarker(record, ros::Time(3.0), options, &marker);
  EXPECT_EQ(marker.ns, "contacts");
  EXPECT_EQ(marker.type, visualization_msgs::Marker::SPHERE_LIST);
  EXPECT_EQ(marker.action, visualization_msgs::Marker::ADD);
  ASSERT_EQ(marker.points.size(), 2u);
  EXPECT_EQ(marker.points[0].x, 1.0);
  EXPECT_EQ(marker.points[1].x, 2.0);
  EXPECT_NE(marker.colors[0].g, marker.colors[1].g);  // an obstacle and a tether apart
  EXPECT_NEAR(marker.scale.x, 0.15, 1e-12);
  record.clear();
  toContactMarker(record, ros::Time(3.1), options, &marker);
  EXPECT_EQ(marker.action, visualization_msgs::Marker::DELETE);
  EXPECT_TRUE(marker.points.empty());
}

// An obstacle whose tf frame never comes keeps its pose and is warned of with a throttle of its own
// (ObstacleFrames, what ObstacleScene logs): one ROS_WARN_THROTTLE line warned of the first missing frame and hid
// every other obstacle's for its 5 s, as LogThrottle.EachOwnerIsDueOncePerPeriodOfItsOwn shows of tethers. Two
// obstacles on missing frames are both warned of at 10 s, neither again before 15 s (kMissingFramePeriod), both at
// 15 s; once a's frame comes, a moves there (its local pose the identity: to the frame's origin, to 1e-12 m) and is
// no longer warned of, while b is again at 20 s, 5 s after its last. An obstacle in the world frame is never looked up.
TEST(Obstacles, EachMissingFrameIsWarnedOfWithAThrottleOfItsOwn)
{
  WorldOptions options;
  ASSERT_EQ(loadObstacles("{obstacles: [{name: a, type: sphere, radius: 0.5, frame: fa},"
                          "{name: b, type: sphere, radius: 0.5, frame: fb},"
                          "{name: fixed, type: sphere, radius: 0.5, position: [5, 0, 0]}]}",
                          &options),
            "");
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  for (const ObstacleSpec& spec : options.obstacles)
  {
    Status status;
    obstacles.push_back(makePrimitive(spec, &status));
    ASSERT_TRUE(obstacles.back()) << status.message;
  }
  World world;
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  tf2_ros::Buffer tf;
  ObstacleFrames frames("world", world, tf);
  std::vector<std::string> warnings;
  const auto names = [&warnings]
  {
    std::string said;
    for (const std::string& warning : warnings)
    {
      said += warning.substr(0, warning.find(':')) + ";";
    }
    warnings.clear();
    return said;
  };
  EXPECT_FALSE(frames.follow(ros::Time(10.0), &warnings));
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[1].rfind("obstacle 'b' keeps its last pose: no transform world -> fb", 0), 0u) << warnings[1];
  EXPECT_EQ(names(), "obstacle 'a' keeps its last pose;obstacle 'b' keeps its last pose;")
      << "each obstacle's warning, not the first's alone";
  EXPECT_FALSE(frames.follow(ros::Time(14.9), &warnings));
  EXPECT_EQ(names(), "");
  EXPECT_FALSE(frames.follow(ros::Time(15.0), &warnings));
  EXPECT_EQ(names(), "obstacle 'a' keeps its last pose;obstacle 'b' keeps its last pose;");

  geometry_msgs::TransformStamped fa;
  fa.header.stamp = ros::Time(15.5);
  fa.header.frame_id = "world";
  fa.child_frame_id = "fa";
  fa.transform.translation.x = 1.0, fa.transform.translation.y = 2.0, fa.transform.translation.z = 3.0;
  fa.transform.rotation.w = 1.0;
  ASSERT_TRUE(tf.setTransform(fa, "test", true));
  EXPECT_TRUE(frames.follow(ros::Time(16.0), &warnings)) << "a moved to its frame";
  EXPECT_EQ(names(), "");
  EXPECT_LT((world.obstacle(0).pose().translation() - Eigen::Vector3d(1.0, 2.0, 3.0)).norm(), 1e-12);
  EXPECT_FALSE(frames.follow(ros::Time(20.0), &warnings)) << "a stays where its frame is";
  EXPECT_EQ(names(), "obstacle 'b' keeps its last pose;");
  EXPECT_EQ(world.obstacle(2).pose().translation(), Eigen::Vector3d(5.0, 0.0, 0.0));
}

// ~topology carries World::topology line for line, with the names of the tethers and obstacles.
TEST(Obstacles, TopologyMessageNamesTethersAndObjects)
{
  TetherParams params;
  params.noise = 0.0;
  World world;
  ASSERT_TRUE(world.add("a", std::make_unique<Tether>(params, Position::Zero(), Position(2.0, 0.0, 0.0))).ok);
  ASSERT_TRUE(world.add("b", std::make_unique<Tether>(params, Position(0, 1, 0), Position(2.0, 1.0, 0.0))).ok);
  ObstacleSpec pillar;
  pillar.name = "pillar";
  pillar.type = ShapeType::Cylinder;
  pillar.position = Position(1.0, 0.5, 0.0);
  pillar.radius = 0.1;
  pillar.length = 4.0;
  Status status;
  std::vector<std::unique_ptr<Obstacle>> obstacles;
  obstacles.push_back(makePrimitive(pillar, &status));
  ASSERT_TRUE(world.setObstacles(std::move(obstacles)).ok);
  std::vector<TopologyEntry> entries;
  world.topology(entries);
  Topology msg;
  toTopologyMessage(world, entries, ros::Time(1.5), "world", &msg);
  EXPECT_EQ(msg.header.frame_id, "world");
  EXPECT_EQ(msg.header.stamp, ros::Time(1.5));
  ASSERT_EQ(msg.entries.size(), entries.size());
  int wraps = 0, links = 0;
  for (std::size_t k = 0; k < entries.size(); ++k)
  {
    EXPECT_EQ(msg.entries[k].tether, world.name(entries[k].tether));
    EXPECT_EQ(msg.entries[k].kind, topologyKindName(entries[k].kind));
    EXPECT_EQ(msg.entries[k].value, entries[k].value);
    wraps +=
        msg.entries[k].kind == "wrap_turns" && msg.entries[k].object == "pillar" && !msg.entries[k].object_is_tether;
    links += msg.entries[k].kind == "linking_number" && msg.entries[k].tether == "a" && msg.entries[k].object == "b" &&
             msg.entries[k].object_is_tether;
  }
  EXPECT_EQ(wraps, 2);  // each tether around the pillar
  EXPECT_EQ(links, 1);  // the pair, once
}

// Issue 21, one builder: the node (its parameters, as WorldNode reads them: loadTetherSetup per tether on top of
// the shared ones, loadWorldOptions, nodeWorldSpec) and the runner (a scenario file, worldSpecOf) describe the
// same world in their own formats; buildWorld must make the same World of both: the same tethers with the same
// parameters and cables laid the same, the same obstacles where they were put, and, stepped alike, the same
// motion bit for bit (contact between tethers and a mesh included).
TEST(WorldSpec, NodeAndRunnerBuildTheSameWorld)
{
  const std::string wreck = std::string(ROV_TETHER_SOURCE_DIR) + "/meshes/wreck.stl";
  const std::string obstacles =
      "[{name: pillar, type: cylinder, radius: 0.5, length: 8, position: [2, 3, -4], "
      "friction: 0.3}, {name: wreck, type: mesh, file: '" +
      wreck + "', position: [4.5, 6, -3.5], orientation: [0, 0, 0.4]}]";
  const YAML::Node node_yaml = YAML::Load(
      "{tethers: [a, b], cable_length: 12, seabed_z: -20, tether_contact: true, obstacles: " + obstacles +
      ", a: {spool_position: [0, 0, 0]}, b: {spool_position: [1, 0, 0], cable_length: 9, segment_length: 0.5}}");
  const XmlRpc::XmlRpcValue top = rov_tether::test::toXmlRpc(node_yaml);
  const std::vector<std::string> names = {"a", "b"};
  std::vector<TetherSetup> setups(names.size());
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    ASSERT_EQ(loadTetherSetup(top, rov_tether::test::toXmlRpc(node_yaml[names[i]]), &setups[i]), "");
  }
  WorldOptions options;
  ASSERT_EQ(loadWorldOptions(top, &options, names), "");
  WorldSpec node_spec;
  ASSERT_EQ(nodeWorldSpec(names, setups, options, &node_spec), "");
  World node_world;
  ASSERT_EQ(buildWorld(node_spec, &node_world, &world_warnings), "");

  Scenario scenario;
  ASSERT_EQ(parseScenario("duration: 1\ntether_contact: true\nobstacles: " + obstacles +
                              "\ntethers:\n  - {name: a, params: {cable_length: 12, seabed_z: -20}, spool: [0, 0, 0]}\n"
                              "  - {name: b, params: {cable_length: 9, segment_length: 0.5, seabed_z: -20}, "
                              "spool: [1, 0, 0]}\n",
                          &scenario),
            "");
  World runner_world;
  ASSERT_EQ(buildWorld(worldSpecOf(scenario), &runner_world, &world_warnings), "");

  ASSERT_EQ(node_world.size(), 2u);
  ASSERT_EQ(runner_world.size(), node_world.size());
  std::vector<Position> node_positions, runner_positions;
  const auto sameTethers = [&]
  {
    for (std::size_t i = 0; i < node_world.size(); ++i)
    {
      EXPECT_EQ(node_world.name(i), runner_world.name(i));
      for (const auto& name : parameterNames())
      {
        EXPECT_TRUE(test::sameParamValue(getParameter(node_world.tether(i).params(), name),
                                         getParameter(runner_world.tether(i).params(), name)))
            << node_world.name(i) << " " << name;
      }
      node_world.tether(i).copyPositions(node_positions);
      runner_world.tether(i).copyPositions(runner_positions);
      EXPECT_EQ(node_positions, runner_positions) << node_world.name(i);
    }
  };
  sameTethers();
  ASSERT_EQ(node_world.obstacleCount(), 2u);
  ASSERT_EQ(runner_world.obstacleCount(), node_world.obstacleCount());
  for (std::size_t k = 0; k < node_world.obstacleCount(); ++k)
  {
    const Obstacle& node = node_world.obstacle(k);
    const Obstacle& runner = runner_world.obstacle(k);
    EXPECT_EQ(node.name(), runner.name());
    EXPECT_EQ(node.spec().type, runner.spec().type);
    EXPECT_EQ(node.spec().friction, runner.spec().friction) << node.name();
    EXPECT_EQ(node.bounds().lo, runner.bounds().lo) << node.name();
    EXPECT_EQ(node.bounds().hi, runner.bounds().hi) << node.name();
  }
  // Stepped alike (no vehicle sample: both free ends fall), they move alike.
  ASSERT_TRUE(node_world.advanceTo(0.5).ok);
  ASSERT_TRUE(runner_world.advanceTo(0.5).ok);
  sameTethers();
}

// Issue 21: one rule for a tether's name, the runner's (isTetherName); the node refuses a name outside it at
// start (WorldNode, parameter `tethers`), and one ROS cannot take as a namespace (~<name>/), with the reason.
TEST(WorldSpec, TheNodeRefusesABadTetherNameClearly)
{
  for (const std::string& good : std::vector<std::string>{"t0", "fast", "rov_1", "tether"})
  {
    EXPECT_EQ(checkNodeTetherName(good), "") << good;
  }
  EXPECT_EQ(checkNodeTetherName(""), "'': expected 1-64 letters, digits, '_' or '-'");
  EXPECT_EQ(checkNodeTetherName("a/b"), "'a/b': expected 1-64 letters, digits, '_' or '-'");
  EXPECT_EQ(checkNodeTetherName("rov 1"), "'rov 1': expected 1-64 letters, digits, '_' or '-'");
  EXPECT_EQ(checkNodeTetherName(std::string(65, 'a')).find("expected 1-64 letters"), std::string(65, 'a').size() + 4);
  // Within the runner's rule, but no ROS name: said so, not left to roscpp's InvalidNameException.
  for (const std::string& bad : std::vector<std::string>{"rov-1", "1rov"})
  {
    EXPECT_NE(checkNodeTetherName(bad).find("'" + bad + "': not a ROS name"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace rov_tether::ros_layer
