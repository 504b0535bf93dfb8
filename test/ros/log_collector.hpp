#pragma once
// What rosconsole prints while a test looks (no master needed).

#include <ros/console.h>

#include <algorithm>
#include <string>
#include <vector>

namespace rov_tether::ros_layer
{

/// Collects what rosconsole prints at WARN, ERROR and INFO while it lives.
struct LogCollector : ros::console::LogAppender
{
  LogCollector() { ros::console::register_appender(this); }
  ~LogCollector() override { ros::console::deregister_appender(this); }
  void log(ros::console::Level level, const char* str, const char*, const char*, int) override
  {
    (level == ros::console::levels::Warn    ? warnings
     : level == ros::console::levels::Error ? errors
                                            : notes)
        .emplace_back(str);
  }
  std::size_t count(const std::vector<std::string>& lines, const std::string& part) const
  {
    return static_cast<std::size_t>(std::count_if(
        lines.begin(), lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; }));
  }
  std::vector<std::string> warnings, errors, notes;
};

}  // namespace rov_tether::ros_layer
