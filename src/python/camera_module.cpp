// rov_tether._camera: a camera looking at a Python World's tethers (docs/python.md), through the renderer the
// node and the runner use (camera::TetherRenderer, camera::CameraScene: every tether as a tube of its diameter,
// the seabed hiding what lies below it). A module of its own, loaded on first use of rov_tether.Camera, so
// `import rov_tether` does not load OpenCV.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "rov_tether/camera/camera_model.hpp"
#include "rov_tether/camera/camera_scene.hpp"
#include "rov_tether/camera/tether_renderer.hpp"
#include "rov_tether/core/status.hpp"
#include "session.hpp"

namespace py = pybind11;

namespace rov_tether::python
{
namespace
{

class Camera
{
 public:
  Camera(int width, int height, const std::vector<double>& k, const std::vector<double>& d)
      : model_(intrinsics(width, height, k, d))
  {
  }

  /// Mask (H x W uint8, 255 where a tether is seen) and depth (H x W float32, metres along the optical axis,
  /// NaN elsewhere) of `world` now, seen from `position` with the optical frame's `orientation`.
  py::tuple render(Session& session, const std::vector<double>& position, const std::vector<double>& orientation)
  {
    if (position.size() != 3 || orientation.size() != 4)
    {
      throw py::value_error("render: position must be [x, y, z] and orientation a quaternion [x, y, z, w]");
    }
    const Eigen::Vector3d p(position[0], position[1], position[2]);
    const Eigen::Quaterniond q(orientation[3], orientation[0], orientation[1], orientation[2]);
    if (!p.allFinite() || !q.coeffs().allFinite() || !(q.norm() > 1e-9))
    {
      throw py::value_error("render: position and orientation must be finite, the quaternion not zero");
    }
    Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
    world_from_camera.linear() = q.normalized().toRotationMatrix();
    world_from_camera.translation() = p;
    const int h = model_.height(), w = model_.width();
    py::array_t<std::uint8_t> mask({h, w});
    py::array_t<float> depth({h, w});
    std::uint8_t* const mask_out = mask.mutable_data();
    float* const depth_out = depth.mutable_data();
    {
      // The camera's lock, then the world's (withWorld releases the GIL): one camera renders for one thread at
      // a time, and the arrays are filled before either lock is let go.
      const py::gil_scoped_release released;
      const std::lock_guard<std::mutex> camera_lock(mutex_);
      const std::lock_guard<std::mutex> world_lock(session.mutex);
      camera::CameraScene scene(session.world);
      scene.record();
      scene.tubesAt(session.world.time(), tubes_);
      renderer_.render(model_, world_from_camera, tubes_, scene.occluders());
      std::copy_n(renderer_.mask().ptr<std::uint8_t>(), static_cast<std::size_t>(h) * w, mask_out);
      std::copy_n(renderer_.depth().ptr<float>(), static_cast<std::size_t>(h) * w, depth_out);
    }
    return py::make_tuple(mask, depth);
  }

  int width() const { return model_.width(); }
  int height() const { return model_.height(); }

 private:
  static camera::CameraIntrinsics intrinsics(int width, int height, const std::vector<double>& k,
                                             const std::vector<double>& d)
  {
    if (k.size() != 9)
    {
      throw py::value_error("K: 9 numbers, row-major (got " + std::to_string(k.size()) + ")");
    }
    camera::CameraIntrinsics in;
    in.width = width;
    in.height = height;
    std::copy(k.begin(), k.end(), in.K.begin());
    in.D = d;
    const std::vector<std::string> errors = in.validate();
    if (!errors.empty())
    {
      throw py::value_error(joinMessages(errors));
    }
    return in;  // CameraModel throws std::invalid_argument (ValueError) for a distortion it cannot invert
  }

  camera::CameraModel model_;
  std::mutex mutex_;  ///< Held while it renders: renderer_ and tubes_ are its working storage.
  camera::TetherRenderer renderer_;
  std::vector<camera::Tube> tubes_;
};

}  // namespace
}  // namespace rov_tether::python

PYBIND11_MODULE(_camera, m)
{
  using rov_tether::python::Camera;
  using rov_tether::python::Session;
  py::module_::import("rov_tether._core");  // the World type
  rov_tether::python::translateMessages();
  m.doc() = "A camera looking at a rov_tether.World's tethers (docs/python.md)";
  py::class_<Camera>(m, "Camera", "A pinhole camera (plumb_bob distortion) that renders a World's tethers")
      .def(py::init<int, int, const std::vector<double>&, const std::vector<double>&>(), py::arg("width"),
           py::arg("height"), py::arg("K"), py::arg("D") = std::vector<double>{},
           "Image size [px], K (3 x 3 row-major, sensor_msgs/CameraInfo's), D (plumb_bob: 0, 4 or 5 numbers)")
      .def("render", &Camera::render, py::arg("world"), py::arg("position"), py::arg("orientation"),
           "(mask, depth) of the world now: mask H x W uint8 (255: tether), depth H x W float32 [m] along the "
           "optical axis (NaN: none); the camera at `position` [m], its optical frame (z forward, x right, y "
           "down) turned by `orientation`, a quaternion [x, y, z, w], in the world frame")
      .def_property_readonly("width", &Camera::width)
      .def_property_readonly("height", &Camera::height);
}
