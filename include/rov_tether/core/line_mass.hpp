#pragma once

namespace rov_tether
{

/// Mass per metre of cable as the water sees it [kg/m]: along the cable (the cable's own) and across it
/// (with Morison's added mass, which acts on the flow across the cable only).
struct LineMass
{
  double along = 0.1;
  double across = 0.1;
};

}  // namespace rov_tether
