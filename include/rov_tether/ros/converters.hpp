#pragma once

#include <geometry_msgs/WrenchStamped.h>
#include <ros/time.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/ColorRGBA.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "rov_tether/GetTension.h"
#include "rov_tether/TetherConfig.h"
#include "rov_tether/TetherCoupling.h"
#include "rov_tether/TetherState.h"
#include "rov_tether/Topology.h"
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

/// Fills a TetherState from the simulation; `tensions` are its segment tensions (spool first) [N].
void toStateMessage(const Tether& sim, const std::vector<double>& tensions, const ros::Time& stamp,
                    const std::string& frame_id, double measured_winch_speed, std::uint32_t resets, TetherState* msg);

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

/// The world's topology report (World::topology) as a ~topology message: objects and tethers by name,
/// kinds by topologyKindName. Reuses `msg`'s storage.
void toTopologyMessage(const World& world, const std::vector<TopologyEntry>& entries, const ros::Time& stamp,
                       const std::string& frame_id, Topology* msg);

/// The tether's tf frames at `stamp`: the spool outlet (`spool_frame`) and the cable's vehicle end, its
/// last particle (`end_frame`), as children of `world_frame` with the world's axes; an empty name leaves
/// that frame out. Reuses `message`'s storage.
void toTransforms(const Tether& sim, const ros::Time& stamp, const std::string& world_frame,
                  const std::string& spool_frame, const std::string& end_frame, tf2_msgs::TFMessage* message);

/// `pull` [N] in `frame_id` (the world frame), with its torque about the vehicle origin [N m]: the lever arm
/// is `attachment_offset` (vehicle frame) turned by the orientation of `vehicle`, the vehicle's pose at the
/// time of the force (the physics' time).
geometry_msgs::WrenchStamped toWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                      const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                      const std::string& frame_id);

/// The same pull in the vehicle's own frame `vehicle_frame`, as a vehicle simulator applies it: force
/// R^T pull and torque attachment_offset x R^T pull, R the orientation of `vehicle` at the force's time.
geometry_msgs::WrenchStamped toVehicleWrench(const Force& pull, const Eigen::Isometry3d& vehicle,
                                             const Eigen::Vector3d& attachment_offset, const ros::Time& stamp,
                                             const std::string& vehicle_frame);

/// ~coupling: `linearisation` (Tether::vehicleEndLinearisation) stamped with its physics time, in `frame_id`
/// (the world frame); F0 is `pull` (Tether::vehicleForce(), what ~wrench gives: no push from a compressed
/// end segment, the half segment's weight always), K and C row-major.
void toCouplingMessage(const EndLinearisation& linearisation, const Force& pull, const std::string& frame_id,
                       TetherCoupling* message);

/// Applies every dynamic_reconfigure field to `params` through the core's setParameter (the .cfg uses
/// the model's parameter names). Returns "" or every problem, each naming its parameter; it does not
/// validate relations between fields (TetherParams::validate() does).
std::string configToParams(const TetherConfig& config, TetherParams* params);

/// The dynamic_reconfigure view of `params` (every field of the .cfg, read by name); `auto` values show as
/// what they resolve to.
TetherConfig paramsToConfig(const TetherParams& params);

/// A dynamic_reconfigure request applied to `requested`, the parameters as the user asked for them (`auto`
/// kept apart from what it resolves to). Only the fields of `asked` that differ from what the server shows,
/// paramsToConfig(*requested), are set: a field left as shown keeps what was asked, so `iterations: auto`
/// stays auto and is resolved again from the new values, while a new number for iterations ends auto.
/// Returns "" or every problem, each naming its parameter (the field's own, then validate()'s, then a change
/// `auto` would override at once: substeps under lumped_mass with `iterations: auto`); `requested` is
/// changed only when there is none.
std::string applyConfigChanges(const TetherConfig& asked, TetherParams* requested);

/// Every numeric field of the .cfg at the table's lower (`upper` false) or upper bound, for the server's
/// setConfigMin/Max: rqt_reconfigure shows these ranges, while the .cfg itself gives none, so the server
/// never clamps a request before the node has checked it.
TetherConfig configBounds(bool upper);

/// The fields in which `asked` differs from `used`, as "name: asked A, used U" joined by "; " ("" if none):
/// the WARN of a refused dynamic_reconfigure change names what was asked and what runs.
std::string configDifferences(const TetherConfig& asked, const TetherConfig& used);

/// Answers a GetTension request from the simulation and its segment tensions.
void answerGetTension(const Tether& sim, const std::vector<double>& tensions, const GetTension::Request& request,
                      GetTension::Response* response);

}  // namespace rov_tether::ros_layer
