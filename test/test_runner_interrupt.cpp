// rov_tether_run stopped from outside: Ctrl-C (SIGINT) or a kill (SIGTERM) in the middle of a run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace rov_tether::test
{
namespace
{

namespace fs = std::filesystem;

std::string readAll(const fs::path& path)
{
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The files in `dir` whose names end in ".partial" (the runner's temporaries), as one line.
std::string partialFiles(const fs::path& dir)
{
  std::string found;
  for (const auto& entry : fs::directory_iterator(dir))
  {
    const std::string name = entry.path().filename().string();
    if (name.size() >= 8 && name.compare(name.size() - 8, 8, ".partial") == 0)
    {
      found += name + " ";
    }
  }
  return found;
}

// A run of the demo's dive made 5000 s long (minutes of CPU) is sent SIGINT, then SIGTERM, once it is writing
// its outputs. Each time the runner stops within seconds, says by what and at which simulated time, exits
// 128 + the signal (130, 143: the shell's convention for a program a signal ended), removes its temporaries
// (.state.csv.partial, .shape.csv.partial) and leaves an earlier run's state.csv as it was. Before, the signal's
// default action ended it: no message, the temporaries left behind (docs/runner.md said so).
TEST(Runner, ASignalStopsTheRunAndLeavesTheOutputDirectoryAsItWas)
{
  const fs::path dir = fs::temp_directory_path() / ("rov_tether_test_interrupt_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::string scenario = readAll(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/spool_payout.yaml");
  const std::size_t at = scenario.find("\nduration: ");
  ASSERT_NE(at, std::string::npos);
  scenario.replace(at + 1, scenario.find('\n', at + 1) - at - 1, "duration: 5000");
  std::ofstream(dir / "long.yaml") << scenario;
  const std::string earlier = "an earlier run's state.csv\n";

  for (const int signal_number : {SIGINT, SIGTERM})
  {
    SCOPED_TRACE(signal_number == SIGINT ? "SIGINT" : "SIGTERM");
    std::ofstream(dir / "out" / "state.csv") << earlier;
    const fs::path err = dir / "stderr.txt";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0)
    {
      const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(fd, 2);
      ::dup2(null, 1);
      ::execl(ROV_TETHER_RUNNER, ROV_TETHER_RUNNER, (dir / "long.yaml").c_str(), "--out", (dir / "out").c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // The temporaries are opened after the handlers are set: once one is there, the run is under way.
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    pid_t ended = 0;
    while (!fs::exists(dir / "out" / ".state.csv.partial") && ended == 0 &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(120))
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      ended = ::waitpid(pid, &status, WNOHANG);
    }
    ASSERT_EQ(ended, 0) << "the runner ended before it was stopped: " << readAll(err);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the steps
    ASSERT_EQ(::kill(pid, signal_number), 0);
    const auto sent = std::chrono::steady_clock::now();
    while (ended == 0 && std::chrono::steady_clock::now() - sent < std::chrono::seconds(60))
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      ended = ::waitpid(pid, &status, WNOHANG);
    }
    if (ended == 0)
    {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      FAIL() << "the runner went on for 60 s after the signal";
    }
    const std::string said = readAll(err);
    ASSERT_TRUE(WIFEXITED(status)) << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << "; "
                                   << said;
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal_number) << said;
    const std::string expected = std::string("rov_tether_run: stopped by ") +
                                 (signal_number == SIGINT ? "SIGINT" : "SIGTERM") + ", interrupted at t = ";
    EXPECT_EQ(said.rfind(expected, 0), 0u) << said;
    EXPECT_NE(said.find("of the scenario's 5000 s: no CSV output was written"), std::string::npos) << said;
    EXPECT_EQ(partialFiles(dir / "out"), "");
    EXPECT_FALSE(fs::exists(dir / "out" / "shape.csv"));
    EXPECT_EQ(readAll(dir / "out" / "state.csv"), earlier);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rov_tether::test
