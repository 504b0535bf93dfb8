#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "rov_tether/camera/camera_model.hpp"
#include "rov_tether/ros/camera_config.hpp"

namespace rov_tether::ros_layer
{

/**
 * Builds a camera's model on a thread of its own. Building inverts the distortion over every pixel, about 2 s for
 * a distorted 1280x720 camera: on the node's callback thread that held the physics, every output and the services
 * as long whenever a CameraInfo brought new intrinsics (and made the physics skip ahead after it). request() hands
 * the intrinsics over and returns at once; take() hands back the model of the last intrinsics requested once it is
 * built, or why it could not be (buildCameraModel's error), and never a superseded or cancelled request's. One
 * build runs at a time; what is requested meanwhile is built after it (only the latest), unless it is what is being
 * built (a good CameraInfo after a refused one cancelled its build): that build is then its. The destructor (the
 * node shutting down) abandons a build in progress: the builder hears it within a stretch of rows
 * (CameraModel::kRowsPerStretch), so the shutdown does not wait seconds for it. The thread starts at the first
 * request. request, cancel, take, pending and requested are for one thread (the callback thread); only the build
 * runs on the worker's.
 */
class CameraModelWorker
{
 public:
  /// A finished build: the model of `intrinsics`, or an empty one and why.
  struct Built
  {
    camera::CameraIntrinsics intrinsics;
    std::unique_ptr<camera::CameraModel> model;
    std::string error;
  };

  /// `build`: what builds a model (CameraModel's constructor when empty; tests give one they control).
  explicit CameraModelWorker(CameraModelBuilder build = {});
  ~CameraModelWorker();
  CameraModelWorker(const CameraModelWorker&) = delete;
  CameraModelWorker& operator=(const CameraModelWorker&) = delete;

  /// Builds the model of `intrinsics` after any build in progress, in place of whatever was requested before.
  void request(const camera::CameraIntrinsics& intrinsics);
  /// Forgets the request: its model, built or not, is never handed back.
  void cancel();
  /// The model of the last request, once built (once: it is moved out), else nothing.
  std::optional<Built> take();
  /// A request whose build has not been taken yet (running, waiting, or finished and not taken).
  bool pending() const { return requested_.has_value(); }
  /// The intrinsics of that request, if any.
  const std::optional<camera::CameraIntrinsics>& requested() const { return requested_; }

 private:
  void run();

  CameraModelBuilder build_;
  std::optional<camera::CameraIntrinsics> requested_;  ///< The callback thread's view: what take() will hand back.
  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t generation_ = 0;                      ///< Counts requests and cancellations; a build keeps its own.
  std::optional<camera::CameraIntrinsics> waiting_;   ///< Requested, not yet started.
  std::optional<camera::CameraIntrinsics> building_;  ///< Being built, on the worker's thread.
  std::uint64_t building_generation_ = 0;  ///< The request that build is for (taken on by a request for the same).
  std::optional<Built> done_;              ///< Built for generation_, not yet taken.
  std::atomic<bool> abandon_{false};       ///< The worker is being destroyed: a build in progress stops.
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace rov_tether::ros_layer
