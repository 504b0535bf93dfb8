// CameraModelWorker (ros/camera_model_worker.hpp): a camera's model is built on a thread of its own, and only the
// last request's comes back. The builder here waits at a gate the test opens, so every check is of order, not of
// time: request() returns while the build is held. (Built on the calling thread, request() would wait at the
// closed gate until its 10 s ran out and the builder gave up, and take() would then hand back that failure at
// once: the first check fails instead of the test hanging.)
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rov_tether/ros/camera_model_worker.hpp"

namespace rov_tether::ros_layer
{
namespace
{

/// Where the builder waits (each build until its width is let through, or all are, or until the worker abandons it),
/// and what it was asked to build (the widths, in order), has built and has abandoned.
struct Gate
{
  std::mutex mutex;
  std::condition_variable changed;
  bool open = false;
  std::vector<int> through, started, finished, abandoned;

  CameraModelBuilder builder()
  {
    return [this](const camera::CameraIntrinsics& intrinsics, const camera::BuildAbandoned& asked)
    {
      std::unique_lock<std::mutex> lock(mutex);
      const int width = intrinsics.width;
      started.push_back(width);
      changed.notify_all();
      const auto let = [&] { return open || std::find(through.begin(), through.end(), width) != through.end(); };
      // The worker says nothing when it abandons a build: the builder asks, as CameraModel does, every 1 ms here.
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (!let())
      {
        if (asked())
        {
          abandoned.push_back(width);
          changed.notify_all();
          throw camera::CameraBuildAbandoned();
        }
        if (std::chrono::steady_clock::now() > end)
        {
          throw std::runtime_error("the gate never opened");
        }
        changed.wait_for(lock, std::chrono::milliseconds(1));
      }
      auto model = std::make_unique<camera::CameraModel>(intrinsics);
      finished.push_back(width);
      changed.notify_all();
      return model;
    };
  }
  void openIt()
  {
    const std::lock_guard<std::mutex> lock(mutex);
    open = true;
    changed.notify_all();
  }
  /// Lets the build of this width through.
  void letThrough(int width)
  {
    const std::lock_guard<std::mutex> lock(mutex);
    through.push_back(width);
    changed.notify_all();
  }
  /// Waits until `count` builds have started (10 s at most).
  bool startedAtLeast(std::size_t count)
  {
    std::unique_lock<std::mutex> lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(10), [&] { return started.size() >= count; });
  }
  /// Waits until `count` builds have finished (10 s at most).
  bool finishedAtLeast(std::size_t count)
  {
    std::unique_lock<std::mutex> lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(10), [&] { return finished.size() >= count; });
  }
};

/// Opens the gate when it goes out of scope: declared after the worker, so the worker's destructor, which waits
/// for a build in progress, never waits at a closed gate (the 10 s until its builder gives up).
struct OpenAtExit
{
  Gate& gate;
  ~OpenAtExit() { gate.openIt(); }
};

camera::CameraIntrinsics intrinsics(int width, int height)
{
  camera::CameraIntrinsics result;
  result.width = width;
  result.height = height;
  result.K = {50, 0, 0.5 * (width - 1), 0, 50, 0.5 * (height - 1), 0, 0, 1};
  return result;
}

/// take() until it hands something back (10 s at most).
std::optional<CameraModelWorker::Built> takeWithin10s(CameraModelWorker& worker)
{
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end)
  {
    if (auto built = worker.take())
    {
      return built;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

/// The width of the model take() hands back within 10 s: -1 when nothing comes, 0 for a build with no model.
int builtWidthWithin10s(CameraModelWorker& worker)
{
  const std::optional<CameraModelWorker::Built> built = takeWithin10s(worker);
  return !built ? -1 : built->model ? built->model->width() : 0;
}

/// A worker whose builder waits at `gate`, opened before the worker is destroyed.
class CameraModelWorkerTest : public testing::Test
{
 protected:
  Gate gate;
  CameraModelWorker worker{gate.builder()};
  OpenAtExit open{gate};  ///< Destroyed before the worker.
};

}  // namespace

// request() hands the intrinsics over and returns while the build is held at the gate; the model comes back
// through take() once built, with the intrinsics asked for, and only once.
TEST_F(CameraModelWorkerTest, ACameraIsBuiltOffTheThreadThatAsks)
{
  worker.request(intrinsics(64, 48));
  EXPECT_FALSE(worker.take().has_value()) << "handed back before the gate opened: built on the calling thread";
  EXPECT_TRUE(worker.pending());
  ASSERT_TRUE(worker.requested().has_value());
  EXPECT_EQ(*worker.requested(), intrinsics(64, 48));
  gate.openIt();
  std::optional<CameraModelWorker::Built> built = takeWithin10s(worker);
  ASSERT_TRUE(built.has_value());
  EXPECT_EQ(built->error, "");
  ASSERT_NE(built->model, nullptr);
  EXPECT_EQ(built->model->width(), 64);
  EXPECT_EQ(built->intrinsics, intrinsics(64, 48));
  EXPECT_FALSE(worker.pending());
  EXPECT_FALSE(worker.take().has_value());
}

// CameraInfos with new intrinsics in quick succession: the one being built when the others came is built out and
// dropped, the one superseded before its build started is never built, and only the last comes back. The next
// build starting shows the worker is done with the one before: nothing is handed back by then.
TEST_F(CameraModelWorkerTest, OnlyTheLastRequestComesBack)
{
  worker.request(intrinsics(64, 48));
  ASSERT_TRUE(gate.startedAtLeast(1));
  worker.request(intrinsics(32, 24));
  worker.request(intrinsics(16, 12));
  gate.letThrough(64);
  ASSERT_TRUE(gate.startedAtLeast(2));
  EXPECT_FALSE(worker.take().has_value()) << "the superseded 64x48 camera was handed back";
  gate.letThrough(16);
  EXPECT_EQ(builtWidthWithin10s(worker), 16);
  const std::lock_guard<std::mutex> lock(gate.mutex);
  EXPECT_EQ(gate.started, (std::vector<int>{64, 16}));
  EXPECT_TRUE(gate.abandoned.empty()) << "a build superseded while it ran was abandoned";
}

// CameraInfos alternating between two cameras faster than a build: each request for what is being built takes that
// build on, so a model comes back (were a superseded build abandoned, none ever would).
TEST_F(CameraModelWorkerTest, CamerasAlternatingFasterThanABuildStillBringAModel)
{
  worker.request(intrinsics(64, 48));
  ASSERT_TRUE(gate.startedAtLeast(1));
  for (int i = 0; i < 5; ++i)
  {
    worker.request(intrinsics(32, 24));
    worker.request(intrinsics(64, 48));
  }
  gate.letThrough(64);
  EXPECT_EQ(builtWidthWithin10s(worker), 64);
  const std::lock_guard<std::mutex> lock(gate.mutex);
  EXPECT_EQ(gate.started, (std::vector<int>{64}));
}

// Destroying the worker (the node shutting down) abandons a build in progress: the destructor returns without the
// build being let through. (It waited for the build: seconds for a distorted camera, here the gate's 10 s.)
TEST(CameraModelWorker, ItsDestructionAbandonsABuildInProgress)
{
  Gate gate;
  {
    CameraModelWorker worker(gate.builder());
    worker.request(intrinsics(64, 48));
    ASSERT_TRUE(gate.startedAtLeast(1));
  }
  const std::lock_guard<std::mutex> lock(gate.mutex);
  EXPECT_EQ(gate.abandoned, (std::vector<int>{64})) << "the destructor waited for the build";
  EXPECT_TRUE(gate.finished.empty());
}

// A refused CameraInfo cancels the build of the one before it: that model never comes back (none within 0.2 s of
// its build's end, where it would come within microseconds), and a later request's does.
TEST_F(CameraModelWorkerTest, ACancelledRequestNeverComesBack)
{
  worker.request(intrinsics(64, 48));
  ASSERT_TRUE(gate.startedAtLeast(1));
  worker.cancel();
  EXPECT_FALSE(worker.pending());
  EXPECT_FALSE(worker.requested().has_value());
  gate.letThrough(64);
  ASSERT_TRUE(gate.finishedAtLeast(1));
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
  bool handed_back = false;
  while (!handed_back && std::chrono::steady_clock::now() < end)
  {
    handed_back = worker.take().has_value();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_FALSE(handed_back) << "the cancelled 64x48 camera was handed back";
  worker.request(intrinsics(32, 24));
  gate.openIt();
  EXPECT_EQ(builtWidthWithin10s(worker), 32);
}

// A refused CameraInfo between two good ones cancels the build of the first; the second asks for what is being
// built, and takes that build on: one build, not a second after it (seconds more for a distorted camera).
TEST_F(CameraModelWorkerTest, ARequestForWhatIsBeingBuiltTakesThatBuildOn)
{
  worker.request(intrinsics(64, 48));
  ASSERT_TRUE(gate.startedAtLeast(1));
  worker.cancel();
  worker.request(intrinsics(64, 48));
  EXPECT_TRUE(worker.pending());
  gate.letThrough(64);
  EXPECT_EQ(builtWidthWithin10s(worker), 64);
  EXPECT_FALSE(worker.pending());
  const std::lock_guard<std::mutex> lock(gate.mutex);
  EXPECT_EQ(gate.started, (std::vector<int>{64}));
}

// A build that fails (out of memory) comes back as the reason, buildCameraModel's, with no model: the camera is
// refused and the node goes on.
TEST(CameraModelWorker, AFailedBuildComesBackAsItsReason)
{
  CameraModelWorker worker(
      [](const camera::CameraIntrinsics&, const camera::BuildAbandoned&) -> std::unique_ptr<camera::CameraModel>
      { throw std::bad_alloc(); });
  worker.request(intrinsics(64, 48));
  std::optional<CameraModelWorker::Built> built = takeWithin10s(worker);
  ASSERT_TRUE(built.has_value());
  EXPECT_EQ(built->error, "building the 64x48 camera ran out of memory");
  EXPECT_EQ(built->model, nullptr);
  EXPECT_FALSE(worker.pending());
}

}  // namespace rov_tether::ros_layer
