#include "rov_tether/ros/reconfigure.hpp"

#include <boost/any.hpp>
#include <string>

namespace rov_tether::ros_layer
{

namespace
{
/// One field of a config as the core's parameter value.
ParamValue configField(const TetherConfig& config, const TetherConfig::AbstractParamDescription& description)
{
  boost::any value;
  description.getValue(config, value);
  if (const auto* d = boost::any_cast<double>(&value))
  {
    return *d;
  }
  if (const auto* i = boost::any_cast<int>(&value))
  {
    return static_cast<std::int64_t>(*i);
  }
  if (const auto* b = boost::any_cast<bool>(&value))
  {
    return *b;
  }
  return boost::any_cast<std::string>(value);
}
}  // namespace

std::string configToParams(const TetherConfig& config, TetherParams* params)
{
  std::string errors;
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const std::string error = setParameter(*params, description->name, configField(config, *description));
    if (!error.empty())
    {
      errors += (errors.empty() ? "" : "; ") + error;
    }
  }
  return errors;
}

std::string applyConfigChanges(const TetherConfig& asked, TetherParams* requested)
{
  const TetherConfig shown = paramsToConfig(*requested);
  TetherParams candidate = *requested;
  std::vector<std::string> changed;
  std::string errors;
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const ParamValue value = configField(asked, *description);
    if (value == configField(shown, *description))
    {
      continue;  // as shown: what the user asked for it stands (`auto` stays auto)
    }
    changed.push_back(description->name);
    const std::string error = setParameter(candidate, description->name, value);
    errors += error.empty() ? "" : (errors.empty() ? "" : "; ") + error;
  }
  for (const std::string& e : errors.empty() ? candidate.validate() : std::vector<std::string>{})
  {
    errors += (errors.empty() ? "" : "; ") + e;
  }
  if (!errors.empty())
  {
    return errors;
  }
  // A change that `auto` would override at once (substeps under lumped_mass with `iterations: auto`) is
  // refused rather than dropped.
  const TetherConfig now = paramsToConfig(candidate);
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const bool was_changed = std::find(changed.begin(), changed.end(), description->name) != changed.end();
    const ParamValue value = configField(asked, *description);
    const ParamValue runs = configField(now, *description);
    if (was_changed && value != runs)
    {
      errors += (errors.empty() ? "" : "; ") + description->name + " = " + formatParamValue(value) +
                ": `iterations: auto` chooses " + formatParamValue(runs) +
                " here; set iterations to a number to choose it";
    }
  }
  if (errors.empty())
  {
    *requested = candidate;
  }
  return errors;
}

TetherConfig paramsToConfig(const TetherParams& params)
{
  // `auto` values are shown as what they chose: the config holds numbers only.
  const TetherParams resolved = params.resolved();
  TetherConfig config = TetherConfig::__getDefault__();
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const ParamValue value = getParameter(resolved, description->name);
    const auto* base = description.get();
    if (const auto* d = dynamic_cast<const TetherConfig::ParamDescription<double>*>(base))
    {
      config.*(d->field) = std::get<double>(value);
    }
    else if (const auto* i = dynamic_cast<const TetherConfig::ParamDescription<int>*>(base))
    {
      config.*(i->field) = static_cast<int>(std::get<std::int64_t>(value));
    }
    else if (const auto* b = dynamic_cast<const TetherConfig::ParamDescription<bool>*>(base))
    {
      config.*(b->field) = std::get<bool>(value);
    }
    else if (const auto* s = dynamic_cast<const TetherConfig::ParamDescription<std::string>*>(base))
    {
      config.*(s->field) = std::get<std::string>(value);
    }
  }
  return config;
}

TetherConfig configBounds(bool upper)
{
  TetherConfig config = TetherConfig::__getDefault__();
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const ParameterInfo* row = nullptr;
    for (const ParameterInfo& candidate : parameterInfo())
    {
      row = candidate.name == description->name ? &candidate : row;
    }
    if (row == nullptr || std::isnan(row->min))
    {
      continue;
    }
    const double bound = upper ? row->max : row->min;
    const auto* base = description.get();
    if (const auto* d = dynamic_cast<const TetherConfig::ParamDescription<double>*>(base))
    {
      config.*(d->field) = bound;
    }
    else if (const auto* i = dynamic_cast<const TetherConfig::ParamDescription<int>*>(base))
    {
      config.*(i->field) = static_cast<int>(bound);
    }
  }
  return config;
}

namespace
{
std::string configValue(const TetherConfig& config, const TetherConfig::AbstractParamDescription& description)
{
  boost::any value;
  description.getValue(config, value);
  if (const auto* d = boost::any_cast<double>(&value))
  {
    return formatParamValue(*d);
  }
  if (const auto* i = boost::any_cast<int>(&value))
  {
    return std::to_string(*i);
  }
  if (const auto* b = boost::any_cast<bool>(&value))
  {
    return *b ? "true" : "false";
  }
  return boost::any_cast<std::string>(value);
}
}  // namespace

std::string configDifferences(const TetherConfig& asked, const TetherConfig& used)
{
  std::string differences;
  for (const auto& description : TetherConfig::__getParamDescriptions__())
  {
    const std::string a = configValue(asked, *description);
    const std::string u = configValue(used, *description);
    if (a != u)
    {
      differences += (differences.empty() ? "" : "; ") + description->name + ": asked " + a + ", used " + u;
    }
  }
  return differences;
}

}  // namespace rov_tether::ros_layer
