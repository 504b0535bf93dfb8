#include "rov_tether/ros/camera_model_worker.hpp"

#include <system_error>
#include <utility>

namespace rov_tether::ros_layer
{

CameraModelWorker::CameraModelWorker(CameraModelBuilder build) : build_(std::move(build)) {}

CameraModelWorker::~CameraModelWorker()
{
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    abandon_ = true;  // a build in progress stops within a stretch of rows, not seconds later
  }
  wake_.notify_one();
  if (thread_.joinable())
  {
    thread_.join();
  }
}

void CameraModelWorker::request(const camera::CameraIntrinsics& intrinsics)
{
  std::optional<Built> superseded;  // freed outside the lock
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++generation_;
    if (building_ == intrinsics)
    {
      // What is being built already (cancelled, or superseded, since): that build is this request's.
      building_generation_ = generation_;
      waiting_.reset();
    }
    else
    {
      // Built after the build in progress, which goes on: were it abandoned, CameraInfos alternating between
      // two cameras faster than a build would never bring a model, where this way each request for what is
      // being built takes that build on.
      waiting_ = intrinsics;
    }
    superseded = std::exchange(done_, std::nullopt);
  }
  requested_ = intrinsics;
  if (!thread_.joinable())
  {
    try
    {
      thread_ = std::thread(&CameraModelWorker::run, this);
    }
    catch (const std::system_error& e)
    {
      // No thread (the process is out of them): the request comes back refused, as a failed build does.
      const std::lock_guard<std::mutex> lock(mutex_);
      waiting_.reset();
      done_ = Built{intrinsics, nullptr, std::string("no thread to build the camera on: ") + e.what()};
      return;
    }
  }
  wake_.notify_one();
}

void CameraModelWorker::cancel()
{
  std::optional<Built> dropped;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    ++generation_;
    waiting_.reset();
    dropped = std::exchange(done_, std::nullopt);
  }
  requested_.reset();
}

std::optional<CameraModelWorker::Built> CameraModelWorker::take()
{
  std::optional<Built> built;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    built = std::exchange(done_, std::nullopt);
  }
  if (built)
  {
    requested_.reset();
  }
  return built;
}

void CameraModelWorker::run()
{
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;)
  {
    wake_.wait(lock, [this] { return stop_ || waiting_.has_value(); });
    if (stop_)
    {
      return;
    }
    Built built;
    built.intrinsics = *waiting_;
    waiting_.reset();
    building_ = built.intrinsics;
    building_generation_ = generation_;
    lock.unlock();
    built.error = buildCameraModel(built.intrinsics, &built.model, build_,
                                   [this] { return abandon_.load(std::memory_order_relaxed); });  // never throws
    lock.lock();
    building_.reset();
    if (building_generation_ == generation_)
    {
      done_ = std::move(built);
    }
    else
    {
      lock.unlock();  // a superseded or cancelled request's model, freed outside the lock
      built.model.reset();
      lock.lock();
    }
  }
}

}  // namespace rov_tether::ros_layer
