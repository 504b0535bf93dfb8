#pragma once
// How the ROS layer draws a tether and its world in rviz: the cable coloured by tension, its sections and
// attachments, the colour legend, the obstacles and the contact points (free functions over the core's types).

#include <ros/time.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/ColorRGBA.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "rov_tether/core/tether.hpp"
#include "rov_tether/core/world.hpp"

namespace rov_tether::ros_layer
{

/// How the cable is drawn in rviz.
struct MarkerOptions
{
  std::string frame_id = "world";
  std::string ns = "tether";
  double line_width = 0.03;          ///< [m]
  double tension_full_scale = 50.0;  ///< Tension drawn red [N].
  int stripe_segments = 5;           ///< Segments per stripe; stripes move with the cable as it pays out.
};

/**
 * Colour of a segment carrying `tension` [N]: from light blue (0 N) through cyan, green and yellow to red
 * at `full_scale` and above; compression (negative) is grey. `stripe` lightens it (40% towards white) for
 * the alternate stripes. Every colour stands out on rviz's dark backgrounds (contrast ratio 3 or more).
 */
std_msgs::ColorRGBA tensionColor(double tension, double full_scale, bool stripe);

/**
 * Draws the deployed cable: marker id 0, a LINE_LIST coloured per segment by tension with stripes; id 1
 * the spool (cylinder); id 2 the attachment point (sphere, deleted without a vehicle); id 3 a text with
 * deployed length and tension at the vehicle. Reuses `markers`' storage.
 */
void toMarkers(const Tether& sim, const std::vector<double>& tensions, const ros::Time& stamp,
               const MarkerOptions& options, visualization_msgs::MarkerArray* markers);

/**
 * Draws a cable of sections and attachments (issue 22), markers from `first_id` on: a LINE_LIST twice the line's
 * width in each section's colour over the tension colours (namespace `<ns>_sections`, from the vehicle end:
 * white, pink, green, orange, repeating; DELETE when a live change made the sections the tether's material), then
 * a SPHERE per attachment where its material is, the size of a sphere of water weighing its net buoyancy,
 * yellow for a float, grey for a clump weight (`<ns>_attachments`; DELETE while on the drum). Nothing for a
 * tether without sections or attachments. Reuses `markers`' storage.
 */
void toMaterialMarkers(const Tether& sim, const ros::Time& stamp, const MarkerOptions& options, std::size_t first_id,
                       visualization_msgs::MarkerArray* markers);

/// Size of the colour legend image (toLegendImage) and the width of its swatches [px].
constexpr int kLegendWidth = 300;
constexpr int kLegendHeight = 190;
constexpr int kLegendSwatch = 40;

/**
 * The cable's colour legend as an image (bgr8, kLegendWidth x kLegendHeight, on config/tether.rviz's
 * background), for rviz's Image display, which keeps it beside the 3D view whatever the view: "cable
 * tension", a swatch of the colour tensionColor gives at 0, 1/4, 1/2, 3/4 and all of `tension_full_scale`
 * with its value, the compression grey ("grey: compression (pushed)"), and a swatch half plain, half
 * lighter for the stripes of `stripe_segments`. Reuses `image`'s storage.
 */
void toLegendImage(const MarkerOptions& options, sensor_msgs::Image* image);

/// Side of the square that draws a plane obstacle, and its thickness (a plane is unbounded; rviz gets a
/// thin square slab just below its surface) [m].
constexpr double kPlaneMarkerSize = 100.0;
constexpr double kPlaneMarkerThickness = 0.01;

/**
 * Draws the world's obstacles where they are now, in `frame_id` (the world frame), namespace "obstacles",
 * and their names above them (namespace "obstacle_names"): a sphere as a SPHERE, a box as a CUBE, a
 * cylinder as a CYLINDER (rviz's is along its local z, as ours), a capsule as a CYLINDER and two SPHEREs
 * at its ends, a plane as a thin CUBE of kPlaneMarkerSize below its surface, a mesh as a MESH_RESOURCE
 * of its file (meshResourceUri) at its scale. Replaces `markers`' content.
 */
void toObstacleMarkers(const World& world, const ros::Time& stamp, const std::string& frame_id,
                       visualization_msgs::MarkerArray* markers);

/// The points where the tether touched an obstacle (orange) or a tether (magenta; itself included) in its
/// last step, from its ContactRecord, as a SPHERE_LIST in namespace "contacts" (id 0) of diameter 3 x the
/// cable's line width; DELETE when it touches nothing.
void toContactMarker(const ContactRecord& record, const ros::Time& stamp, const MarkerOptions& options,
                     visualization_msgs::Marker* marker);

}  // namespace rov_tether::ros_layer
