#include "rov_tether/ros/markers.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "rov_tether/core/cable_sections.hpp"
#include "rov_tether/ros/obstacle_config.hpp"

namespace rov_tether::ros_layer
{
namespace
{

geometry_msgs::Point toPoint(const Position& p)
{
  geometry_msgs::Point point;
  point.x = p.x();
  point.y = p.y();
  point.z = p.z();
  return point;
}

std_msgs::ColorRGBA rgba(double r, double g, double b, double a = 1.0)
{
  std_msgs::ColorRGBA color;
  color.r = static_cast<float>(r);
  color.g = static_cast<float>(g);
  color.b = static_cast<float>(b);
  color.a = static_cast<float>(a);
  return color;
}

/// Marker `id` of the array (grown when needed), with header, namespace, type, ADD and identity pose.
visualization_msgs::Marker& startMarker(visualization_msgs::MarkerArray* markers, std::size_t id, int type,
                                        const std_msgs::Header& header, const std::string& ns)
{
  if (markers->markers.size() <= id)
  {
    markers->markers.resize(id + 1);
  }
  visualization_msgs::Marker& marker = markers->markers[id];
  marker.header = header;
  marker.ns = ns;
  marker.id = static_cast<int>(id);
  marker.type = type;
  marker.action = visualization_msgs::Marker::ADD;
  marker.pose.orientation.w = 1.0;
  return marker;
}

/// True when segments j and j + 1 are of one material (the same section).
bool sameMaterial(const CableLoading& load, std::size_t j)
{
  for (const auto* v : {&load.mass_along, &load.mass_across, &load.weight, &load.normal_drag, &load.tangential_drag,
                        &load.axial_stiffness, &load.axial_damping, &load.bending_stiffness})
  {
    if ((*v)[j] != (*v)[j + 1])
    {
      return false;
    }
  }
  return true;
}

/// Section colours, from the vehicle end, repeating: far apart in hue from each other.
std_msgs::ColorRGBA sectionColor(std::size_t section)
{
  static const double palette[][3] = {{0.95, 0.95, 0.95}, {1.0, 0.4, 0.8}, {0.3, 1.0, 0.5}, {1.0, 0.6, 0.1}};
  const auto& c = palette[section % 4];
  return rgba(c[0], c[1], c[2], 0.45);
}

}  // namespace

std_msgs::ColorRGBA tensionColor(double tension, double full_scale, bool stripe)
{
  // Stripes are lighter, not darker: rviz's backgrounds are dark, and a darker stripe of blue or red
  // vanished in them.
  const auto shade = [stripe](double c) { return stripe ? c + 0.4 * (1.0 - c) : c; };
  if (!(tension >= 0.0))  // compression, and NaN
  {
    return rgba(shade(0.55), shade(0.55), shade(0.55));
  }
  // Piecewise-linear light blue -> cyan -> green -> yellow -> red over [0, full_scale].
  const double u = std::min(tension / full_scale, 1.0) * 4.0;
  double r = 0.0, g = 0.0, b = 0.0;
  if (u < 1.0)
  {
    r = 0.3 * (1.0 - u), g = 0.55 + 0.45 * u, b = 1.0;
  }
  else if (u < 2.0)
  {
    g = 1.0, b = 2.0 - u;
  }
  else if (u < 3.0)
  {
    r = u - 2.0, g = 1.0;
  }
  else
  {
    r = 1.0, g = 4.0 - u;
  }
  return rgba(shade(r), shade(g), shade(b));
}

void toMarkers(const Tether& sim, const std::vector<double>& tensions, const ros::Time& stamp,
               const MarkerOptions& options, visualization_msgs::MarkerArray* markers)
{
  const std::size_t particles = sim.deployedParticleCount();
  const std::size_t first = sim.state().first;  // particle identity: stripes travel with the cable

  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = options.frame_id;
  visualization_msgs::Marker& cable =
      startMarker(markers, 0, visualization_msgs::Marker::LINE_LIST, header, options.ns);
  cable.scale.x = options.line_width;
  cable.points.resize(2 * (particles - 1));
  cable.colors.resize(2 * (particles - 1));
  for (std::size_t k = 0; k + 1 < particles; ++k)
  {
    const bool stripe = ((first + k) / static_cast<std::size_t>(options.stripe_segments)) % 2 == 1;
    const std_msgs::ColorRGBA color =
        tensionColor(k < tensions.size() ? tensions[k] : 0.0, options.tension_full_scale, stripe);
    cable.points[2 * k] = toPoint(sim.particle(k));
    cable.points[2 * k + 1] = toPoint(sim.particle(k + 1));
    cable.colors[2 * k] = color;
    cable.colors[2 * k + 1] = color;
  }

  visualization_msgs::Marker& spool = startMarker(markers, 1, visualization_msgs::Marker::CYLINDER, header, options.ns);
  spool.pose.position = toPoint(sim.particle(0));
  spool.scale.x = spool.scale.y = 0.3;
  spool.scale.z = 0.2;
  spool.color = rgba(0.9, 0.6, 0.1);

  visualization_msgs::Marker& attachment =
      startMarker(markers, 2, visualization_msgs::Marker::SPHERE, header, options.ns);
  attachment.action = sim.vehicleAttached() ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
  attachment.pose.position = toPoint(sim.particle(particles - 1));
  attachment.scale.x = attachment.scale.y = attachment.scale.z = 4.0 * options.line_width;
  attachment.color = rgba(1.0, 1.0, 1.0);

  visualization_msgs::Marker& label =
      startMarker(markers, 3, visualization_msgs::Marker::TEXT_VIEW_FACING, header, options.ns);
  label.pose.position = toPoint(sim.particle(particles - 1) + Position(0.0, 0.0, 0.4));
  label.scale.z = 0.25;
  label.color = rgba(1.0, 1.0, 1.0);
  char text[96];
  std::snprintf(text, sizeof(text), "%.2f m out, %.2f N", sim.deployedLength(),
                tensions.empty() ? 0.0 : tensions.back());
  label.text = text;
}

void toMaterialMarkers(const Tether& sim, const ros::Time& stamp, const MarkerOptions& options, std::size_t id,
                       visualization_msgs::MarkerArray* markers)
{
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = options.frame_id;
  const Cable& cable = sim.state();
  const CableLoading& load = cable.loading;
  const TetherParams& p = sim.params();
  if (p.sections.empty() && p.attachments.empty())
  {
    return;  // a uniform cable, and it stays one (sections are not live)
  }
  visualization_msgs::Marker& sections =
      startMarker(markers, id, visualization_msgs::Marker::LINE_LIST, header, options.ns + "_sections");
  sections.points.clear();
  sections.colors.clear();
  if (load.empty())
  {
    sections.action = visualization_msgs::Marker::DELETE;  // sections a live change made the tether's material
    return;
  }
  const std::size_t n = cable.size();
  const std::size_t f = cable.first;
  sections.scale.x = 2.0 * options.line_width;
  std::size_t section = 0;  // counted from the vehicle end
  bool several = false;
  for (std::size_t j = n - 1; j-- > f;)
  {
    if (j + 2 < n && !sameMaterial(load, j))
    {
      ++section, several = true;
    }
    sections.points.push_back(toPoint(cable.position(j + 1)));
    sections.points.push_back(toPoint(cable.position(j)));
    sections.colors.push_back(sectionColor(section));
    sections.colors.push_back(sectionColor(section));
  }
  for (std::size_t j = f; j-- > 0 && !several;)
  {
    several = j + 2 < n && !sameMaterial(load, j);  // a boundary still on the drum
  }
  sections.action = several ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
  for (std::size_t a = 0; a < p.attachments.size(); ++a)
  {
    const CableAttachment& attachment = p.attachments[a];
    visualization_msgs::Marker& sphere =
        startMarker(markers, id + 1 + a, visualization_msgs::Marker::SPHERE, header, options.ns + "_attachments");
    // Where its material is: between the two particles it is shared by (CableSections::load).
    const CableSections::Place place = CableSections::placeOf(p, n, attachment);
    sphere.action = place.far >= f ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;  // drum
    sphere.pose.position =
        toPoint((1.0 - place.far_share) * cable.position(place.near) + place.far_share * cable.position(place.far));
    constexpr double kPi = 3.14159265358979323846;
    const double volume = std::abs(attachment.net_buoyancy) / (p.water_density * 9.81);
    const double diameter = std::cbrt(6.0 * volume / kPi);
    sphere.scale.x = sphere.scale.y = sphere.scale.z =
        std::isfinite(diameter) ? std::max(diameter, 2.0 * options.line_width) : 2.0 * options.line_width;
    sphere.color = attachment.net_buoyancy >= 0.0 ? rgba(1.0, 0.85, 0.1) : rgba(0.45, 0.45, 0.5);
  }
}

void toLegendImage(const MarkerOptions& options, sensor_msgs::Image* image)
{
  const double full = options.tension_full_scale;
  char value[5][48];
  for (int k = 0; k < 4; ++k)
  {
    std::snprintf(value[k], sizeof(value[k]), "%.3g N", 0.25 * k * full);
  }
  std::snprintf(value[4], sizeof(value[4]), "%.3g N and more", full);
  char stripes[64];
  std::snprintf(stripes, sizeof(stripes), "lighter: stripes of %d segments", options.stripe_segments);
  const auto bgr = [](const std_msgs::ColorRGBA& c)
  {
    const auto byte = [](float v) { return std::lround(255.0 * std::clamp(static_cast<double>(v), 0.0, 1.0)); };
    return cv::Scalar(byte(c.b), byte(c.g), byte(c.r));
  };
  cv::Mat legend(kLegendHeight, kLegendWidth, CV_8UC3, cv::Scalar(64, 38, 12));  // config/tether.rviz's background
  const cv::Scalar white(255, 255, 255);
  const auto text = [&](int row, const char* words)
  { cv::putText(legend, words, cv::Point(62, 24 + 22 * row), cv::FONT_HERSHEY_SIMPLEX, 0.45, white, 1, cv::LINE_AA); };
  // A swatch of the colour the cable gets, then what it means.
  const auto swatch = [&](int row, const cv::Scalar& colour)
  { cv::rectangle(legend, cv::Rect(12, 13 + 22 * row, kLegendSwatch, 12), colour, cv::FILLED); };
  cv::putText(legend, "cable tension", cv::Point(12, 24), cv::FONT_HERSHEY_SIMPLEX, 0.5, white, 1, cv::LINE_AA);
  for (int k = 0; k < 5; ++k)
  {
    swatch(1 + k, bgr(tensionColor(0.25 * k * full, full, false)));
    text(1 + k, value[k]);
  }
  swatch(6, bgr(tensionColor(-1.0, full, false)));
  text(6, "grey: compression (pushed)");
  swatch(7, bgr(tensionColor(0.0, full, false)));
  cv::rectangle(legend, cv::Rect(12 + kLegendSwatch / 2, 13 + 22 * 7, kLegendSwatch / 2, 12),
                bgr(tensionColor(0.0, full, true)), cv::FILLED);
  text(7, stripes);

  image->header.frame_id.clear();
  image->height = static_cast<std::uint32_t>(legend.rows);
  image->width = static_cast<std::uint32_t>(legend.cols);
  image->encoding = "bgr8";
  image->is_bigendian = 0;
  image->step = static_cast<std::uint32_t>(legend.cols * 3);
  image->data.assign(legend.data, legend.data + legend.total() * legend.elemSize());
}

namespace
{

geometry_msgs::Pose toPose(const Eigen::Isometry3d& pose)
{
  geometry_msgs::Pose out;
  out.position = toPoint(pose.translation());
  const Eigen::Quaterniond q(pose.linear());
  out.orientation.x = q.x();
  out.orientation.y = q.y();
  out.orientation.z = q.z();
  out.orientation.w = q.w();
  return out;
}

}  // namespace

void toObstacleMarkers(const World& world, const ros::Time& stamp, const std::string& frame_id,
                       visualization_msgs::MarkerArray* markers)
{
  markers->markers.clear();
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = frame_id;
  const std_msgs::ColorRGBA colour = rgba(0.62, 0.55, 0.45, 0.6);  // weathered concrete; the cable shows through
  const auto add = [&](int type, const Eigen::Isometry3d& pose,
                       const Eigen::Vector3d& scale) -> visualization_msgs::Marker&
  {
    visualization_msgs::Marker& marker = startMarker(markers, markers->markers.size(), type, header, "obstacles");
    marker.pose = toPose(pose);
    marker.scale.x = scale.x();
    marker.scale.y = scale.y();
    marker.scale.z = scale.z();
    marker.color = colour;
    return marker;
  };
  std::vector<std::pair<std::string, Position>> labels;
  for (std::size_t i = 0; i < world.obstacleCount(); ++i)
  {
    const Obstacle& obstacle = world.obstacle(i);
    const ObstacleSpec& spec = obstacle.spec();
    const Eigen::Isometry3d& pose = obstacle.pose();
    const double d = 2.0 * spec.radius;
    double top = 0.0;  // [m] above the obstacle's origin along world z, where its name goes
    switch (spec.type)
    {
      case ShapeType::Sphere:
        add(visualization_msgs::Marker::SPHERE, pose, Eigen::Vector3d::Constant(d));
        top = spec.radius;
        break;
      case ShapeType::Box:
        add(visualization_msgs::Marker::CUBE, pose, spec.size);
        top = 0.5 * (pose.linear().cwiseAbs() * spec.size).z();
        break;
      case ShapeType::Cylinder:
        add(visualization_msgs::Marker::CYLINDER, pose, Eigen::Vector3d(d, d, spec.length));
        top = 0.5 * std::abs(pose.linear()(2, 2)) * spec.length + spec.radius;
        break;
      case ShapeType::Capsule:
        add(visualization_msgs::Marker::CYLINDER, pose, Eigen::Vector3d(d, d, spec.length));
        for (const double end : {-0.5, 0.5})
        {
          add(visualization_msgs::Marker::SPHERE, pose * Eigen::Translation3d(0.0, 0.0, end * spec.length),
              Eigen::Vector3d::Constant(d));
        }
        top = 0.5 * std::abs(pose.linear()(2, 2)) * spec.length + spec.radius;
        break;
      case ShapeType::Plane:
        add(visualization_msgs::Marker::CUBE, pose * Eigen::Translation3d(0.0, 0.0, -0.5 * kPlaneMarkerThickness),
            Eigen::Vector3d(kPlaneMarkerSize, kPlaneMarkerSize, kPlaneMarkerThickness));
        break;
      case ShapeType::Mesh:
      {
        visualization_msgs::Marker& mesh =
            add(visualization_msgs::Marker::MESH_RESOURCE, pose, Eigen::Vector3d::Constant(spec.scale));
        mesh.mesh_resource = meshResourceUri(spec.file);
        top = obstacle.bounds().hi.z() - pose.translation().z();
        break;
      }
    }
    labels.emplace_back(spec.name, pose.translation() + Position(0.0, 0.0, top + 0.3));
  }
  for (const auto& [name, at] : labels)
  {
    visualization_msgs::Marker& label = startMarker(
        markers, markers->markers.size(), visualization_msgs::Marker::TEXT_VIEW_FACING, header, "obstacle_names");
    label.pose.position = toPoint(at);
    label.scale.z = 0.3;
    label.color = rgba(1.0, 1.0, 1.0);
    label.text = name;
  }
}

void toContactMarker(const ContactRecord& record, const ros::Time& stamp, const MarkerOptions& options,
                     visualization_msgs::Marker* marker)
{
  marker->header.stamp = stamp;
  marker->header.frame_id = options.frame_id;
  marker->ns = "contacts";
  marker->id = 0;
  marker->type = visualization_msgs::Marker::SPHERE_LIST;
  marker->pose = geometry_msgs::Pose();
  marker->pose.orientation.w = 1.0;
  marker->scale.x = marker->scale.y = marker->scale.z = 3.0 * options.line_width;
  marker->color = rgba(1.0, 0.5, 0.0);
  marker->points.clear();
  marker->colors.clear();
  for (std::size_t j = 0; j < record.point.size(); ++j)
  {
    const bool obstacle = record.obstacle[j] >= 0, tether = record.tether[j] >= 0;
    if (obstacle || tether)
    {
      marker->points.push_back(toPoint(record.point[j]));
      marker->colors.push_back(obstacle ? rgba(1.0, 0.5, 0.0) : rgba(1.0, 0.2, 1.0));
    }
  }
  marker->action = marker->points.empty() ? visualization_msgs::Marker::DELETE : visualization_msgs::Marker::ADD;
}

}  // namespace rov_tether::ros_layer
