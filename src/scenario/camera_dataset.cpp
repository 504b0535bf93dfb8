#include "rov_tether/scenario/camera_dataset.hpp"

#include "rov_tether/geometry/module.hpp"

namespace rov_tether
{

std::unique_ptr<CameraDataset> makeCameraDataset(const Scenario& scenario, const std::string& out_dir,
                                                 std::string* error)
{
  // The module's entry point (camera/dataset_writer.cpp): the writer, or null with the reason in `error`.
  using Make = CameraDataset* (*)(const Scenario* scenario, const std::string* out_dir, std::string* error);
  std::string why;
  const auto make =
      reinterpret_cast<Make>(moduleFunction("librov_tether_camera.so", "rov_tether_make_camera_dataset", &why));
  if (make == nullptr)
  {
    *error = "cameras need the rov_tether_camera module: " + why;
    return nullptr;
  }
  return std::unique_ptr<CameraDataset>(make(&scenario, &out_dir, error));
}

}  // namespace rov_tether
