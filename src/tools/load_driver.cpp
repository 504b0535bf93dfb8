// rov_tether_load: drives tether_node for the load and soak runs of scripts/load.sh. Publishes vehicle
// poses on one or more topics at a given rate (vehicles circling), optionally owns /clock at a speed-up,
// and reports what the node says in /diagnostics (physics real-time factor, step time, load, iterations,
// level) with the node's resident memory (VmRSS of --pid).
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{

struct Options
{
  std::vector<std::string> topics{"rov_pose"};
  double rate = 50.0;        // poses per (ROS) second per topic
  double duration = 30.0;    // ROS seconds
  double clock_speed = 0.0;  // 0: wall time; else publish /clock this many times faster than wall time
  double report = 5.0;       // ROS seconds between report lines
  double spacing = 0.0;      // x offset between vehicles [m]
  double start[3] = {3.0, 0.0, -1.0};
  double radius = 1.0;   // circle radius [m]
  double period = 20.0;  // circle period [s]
  int pid = 0;
};

struct Seen
{
  double rtf = NAN, step_us = NAN, load = NAN, iterations = NAN, rejected = NAN;
  int level = 0;
  std::string message;
};

std::map<std::string, Seen> seen;

void onDiagnostics(const diagnostic_msgs::DiagnosticArray& msg)
{
  for (const auto& status : msg.status)
  {
    if (status.name.find("tether") == std::string::npos)
    {
      continue;
    }
    Seen& s = seen[status.name];
    s.level = status.level;
    s.message = status.message;
    for (const auto& kv : status.values)
    {
      const double v = std::atof(kv.value.c_str());
      if (kv.key == "physics real-time factor") s.rtf = v;
      if (kv.key == "step time [us]") s.step_us = v;
      if (kv.key == "physics load [% of wall time]") s.load = v;
      if (kv.key == "iterations") s.iterations = v;
      if (kv.key == "rejected poses") s.rejected = v;
    }
  }
}

double residentMegabytes(int pid)
{
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind("VmRSS:", 0) == 0)
    {
      return std::atof(line.c_str() + 6) / 1024.0;
    }
  }
  return NAN;
}

std::vector<std::string> split(const std::string& text)
{
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
  {
    if (!item.empty())
    {
      out.push_back(item);
    }
  }
  return out;
}

/// Reads the command line (`--key value` pairs); false (after printing the usage) on an unknown key.
bool parseOptions(int argc, char** argv, Options* options)
{
  Options& o = *options;
  for (int i = 1; i + 1 < argc; i += 2)
  {
    const std::string key = argv[i];
    const std::string value = argv[i + 1];
    if (key == "--topics")
      o.topics = split(value);
    else if (key == "--rate")
      o.rate = std::atof(value.c_str());
    else if (key == "--duration")
      o.duration = std::atof(value.c_str());
    else if (key == "--clock-speed")
      o.clock_speed = std::atof(value.c_str());
    else if (key == "--report")
      o.report = std::atof(value.c_str());
    else if (key == "--spacing")
      o.spacing = std::atof(value.c_str());
    else if (key == "--radius")
      o.radius = std::atof(value.c_str());
    else if (key == "--pid")
      o.pid = std::atoi(value.c_str());
    else if (key == "--start")
    {
      const auto parts = split(value);
      for (std::size_t k = 0; k < 3 && k < parts.size(); ++k) o.start[k] = std::atof(parts[k].c_str());
    }
    else
    {
      std::fprintf(stderr,
                   "usage: rov_tether_load [--topics a,b] [--rate Hz] [--duration s] [--clock-speed x] [--report s]\n"
                   "                       [--spacing m] [--start x,y,z] [--radius m] [--pid PID]\n");
      return false;
    }
  }
  return true;
}

/// Publishes every vehicle's pose on its circle for each pose time up to `now`; counts them in `poses`.
void publishPoses(const Options& o, std::vector<ros::Publisher>& pubs, double start_time, double now, double* next_pose,
                  std::size_t* poses)
{
  while (*next_pose <= now)
  {
    const double t = *next_pose - start_time;
    const double angle = 2.0 * M_PI * t / o.period;
    for (std::size_t k = 0; k < pubs.size(); ++k)
    {
      geometry_msgs::PoseStamped msg;
      msg.header.stamp = o.clock_speed > 0.0 ? ros::Time(*next_pose) : ros::Time::now();
      msg.header.frame_id = "world";
      msg.pose.position.x = o.start[0] + o.spacing * static_cast<double>(k) + o.radius * std::cos(angle);
      msg.pose.position.y = o.start[1] + o.radius * std::sin(angle);
      msg.pose.position.z = o.start[2];
      msg.pose.orientation.w = 1.0;
      pubs[k].publish(msg);
      ++*poses;
    }
    *next_pose += 1.0 / o.rate;
  }
}

/// What the report lines saw, for the summary: the node's memory and each tether's step time and RTF.
struct Totals
{
  double rss_first = NAN, rss_last = NAN, rss_max = 0.0;
  std::map<std::string, double> step_first, step_last, rtf_min;
};

/// Prints one report line (ROS time since the start, the node's RSS, each tether's diagnostics).
void reportLine(const Options& o, double elapsed, Totals& totals)
{
  const double rss = o.pid > 0 ? residentMegabytes(o.pid) : NAN;
  if (std::isnan(totals.rss_first)) totals.rss_first = rss;
  totals.rss_last = rss;
  totals.rss_max = std::max(totals.rss_max, std::isnan(rss) ? 0.0 : rss);
  std::printf("%8.0f %9.1f ", elapsed, rss);
  for (const auto& [name, s] : seen)
  {
    std::printf(" | %s: %.1fx %.1f us %.1f%% it %.0f rejected %.0f%s", name.c_str(), s.rtf, s.step_us, s.load,
                s.iterations, s.rejected, s.level ? (" [" + s.message + "]").c_str() : "");
    if (!totals.step_first.count(name) && std::isfinite(s.step_us)) totals.step_first[name] = s.step_us;
    totals.step_last[name] = s.step_us;
    totals.rtf_min[name] = totals.rtf_min.count(name) ? std::min(totals.rtf_min[name], s.rtf) : s.rtf;
  }
  std::printf("\n");
  std::fflush(stdout);
}

/// Prints the summary lines: poses sent, the node's memory, each tether's step time and lowest RTF.
void printSummary(const Options& o, std::size_t poses, std::size_t topics, Totals& totals)
{
  std::printf("summary: %zu poses on %zu topic(s) over %.0f ROS s", poses, topics, o.duration);
  if (o.pid > 0)
  {
    std::printf("; node RSS first %.1f MB, last %.1f MB, max %.1f MB", totals.rss_first, totals.rss_last,
                totals.rss_max);
  }
  std::printf("\n");
  for (const auto& [name, first] : totals.step_first)
  {
    std::printf("summary: %s: step time first %.1f us, last %.1f us; lowest physics real-time factor %.1fx\n",
                name.c_str(), first, totals.step_last[name], totals.rtf_min[name]);
  }
}

/// Sleeps until the next loop turn, `tick` wall seconds after the last; skips ahead when far behind.
void waitForTick(double tick, ros::WallTime* wall_next)
{
  *wall_next += ros::WallDuration(tick);
  const ros::WallTime wall_now = ros::WallTime::now();
  if (*wall_next > wall_now)
  {
    (*wall_next - wall_now).sleep();
  }
  else if ((wall_now - *wall_next).toSec() > 0.1)
  {
    *wall_next = wall_now;  // fell behind (machine busy): do not burst
  }
}

}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "rov_tether_load", ros::init_options::AnonymousName);
  Options o;
  if (!parseOptions(argc, argv, &o))
  {
    return 2;
  }
  ros::NodeHandle nh;
  std::vector<ros::Publisher> pubs;
  for (const auto& topic : o.topics)
  {
    pubs.push_back(nh.advertise<geometry_msgs::PoseStamped>(topic, 100));
  }
  ros::Publisher clock_pub;
  double sim_time = 0.0;
  if (o.clock_speed > 0.0)
  {
    clock_pub = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
    sim_time = 1000.0;
  }
  ros::Subscriber diag = nh.subscribe("/diagnostics", 100, onDiagnostics);
  ros::WallDuration(1.0).sleep();  // connections

  const double tick = 0.001;  // wall seconds between loop turns: up to 1 kHz of poses per topic
  const double start_time = o.clock_speed > 0.0 ? sim_time : ros::WallTime::now().toSec();
  double next_pose = start_time, next_report = start_time + o.report;
  Totals totals;
  std::size_t poses = 0;
  ros::WallTime wall_next = ros::WallTime::now();
  std::printf("%8s %9s  %s\n", "ROS t [s]", "RSS [MB]",
              "per tether: real-time factor, step time, physics load, iterations, rejected poses [diagnostics level]");
  for (;;)
  {
    double now;
    if (o.clock_speed > 0.0)
    {
      sim_time += tick * o.clock_speed;
      rosgraph_msgs::Clock clock;
      clock.clock = ros::Time(sim_time);
      clock_pub.publish(clock);
      now = sim_time;
    }
    else
    {
      now = ros::WallTime::now().toSec();
    }
    if (now - start_time > o.duration)
    {
      break;
    }
    publishPoses(o, pubs, start_time, now, &next_pose, &poses);
    if (now >= next_report)
    {
      next_report += o.report;
      reportLine(o, now - start_time, totals);
    }
    ros::spinOnce();
    waitForTick(tick, &wall_next);
  }
  printSummary(o, poses, pubs.size(), totals);
  return 0;
}
