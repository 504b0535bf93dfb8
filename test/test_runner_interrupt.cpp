// Runs that stop in the middle: rov_tether_run stopped from outside (Ctrl-C, SIGINT, or a kill, SIGTERM), and a run
// left by an exception.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rov_tether/scenario/scenario_runner.hpp"
#include "rov_tether/scenario/scenario_yaml.hpp"

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

/// Removes a directory at the end of its scope, whichever way the test leaves it.
struct RemovedAtEnd
{
  fs::path dir;
  ~RemovedAtEnd()
  {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

/// Starts `program` with `arguments` as from an interactive shell (SIGINT and SIGTERM at their default and not
/// blocked: the test itself may have been started in the background, with SIGINT ignored, which the program would
/// keep), its standard error into `err` and its output to /dev/null. Everything is made before fork: the child only
/// calls what is safe after it.
pid_t startProgram(const char* program, const std::vector<std::string>& arguments, const std::string& err)
{
  std::vector<char*> argv{const_cast<char*>(program)};
  for (const std::string& argument : arguments)
  {
    argv.push_back(const_cast<char*>(argument.c_str()));
  }
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0)
  {
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(fd, 2);
    ::dup2(null, 1);
    ::execv(program, argv.data());
    ::_exit(127);
  }
  return pid;
}

/// Waits until `pid` has ended or `seconds` have passed, or (with `until`) until that file is there: the pid if it
/// ended (its status in `status`), else 0.
pid_t waitFor(pid_t pid, int* status, int seconds, const fs::path& until = {})
{
  const auto start = std::chrono::steady_clock::now();
  pid_t ended = 0;
  while (ended == 0 && (until.empty() || !fs::exists(until)) &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(seconds))
  {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ended = ::waitpid(pid, status, WNOHANG);
  }
  return ended;
}

/// Waits until `partial` is there (the program is writing its outputs), lets it run 300 ms more, sends it
/// `signal_number` and waits up to 60 s for it to end (then kills it): "" with its status in `status`, or what went
/// wrong.
std::string stopWhileWriting(pid_t pid, const fs::path& partial, int signal_number, int* status, const std::string& err)
{
  if (waitFor(pid, status, 120, partial) != 0)
  {
    return "it ended before it was stopped: " + readAll(err);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the steps
  if (::kill(pid, signal_number) != 0)
  {
    return "the signal could not be sent";
  }
  if (waitFor(pid, status, 60) == 0)
  {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, status, 0);
    return "it went on for 60 s after the signal";
  }
  return "";
}

// scenarios/spool_payout.yaml (the demo's dive) made 5000 s long (over a minute of CPU) is sent SIGINT, then
// SIGTERM, once it is writing its outputs. Each time the runner stops well before the end (the time it says it
// stopped at: it looks for the signal every 0.25 s of simulated time), says by what, removes its temporaries
// (.state.csv.partial, .shape.csv.partial), leaves an earlier run's state.csv as it was, and then ends by the
// signal, as a program without a handler would (the shell's 130, 143). Before, the signal's default action ended
// it at once: no word, the temporaries left behind.
TEST(Runner, ASignalStopsTheRunAndLeavesTheOutputDirectoryAsItWas)
{
  const RemovedAtEnd scratch{fs::temp_directory_path() / ("rov_tether_test_interrupt_" + std::to_string(::getpid()))};
  const fs::path& dir = scratch.dir;
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::string scenario = readAll(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/spool_payout.yaml");
  const std::size_t at = scenario.find("\nduration: ");
  ASSERT_NE(at, std::string::npos);
  scenario.replace(at + 1, scenario.find('\n', at + 1) - at - 1, "duration: 5000");
  std::ofstream(dir / "long.yaml") << scenario;
  const std::string earlier = "an earlier run's state.csv\n";
  const std::string err = (dir / "stderr.txt").string(), long_yaml = (dir / "long.yaml").string(),
                    out = (dir / "out").string();

  for (const int signal_number : {SIGINT, SIGTERM})
  {
    const char* name = signal_number == SIGINT ? "SIGINT" : "SIGTERM";
    SCOPED_TRACE(name);
    std::ofstream(dir / "out" / "state.csv") << earlier;
    const pid_t pid = startProgram(ROV_TETHER_RUNNER, {long_yaml, "--out", out}, err);
    ASSERT_GE(pid, 0);
    // The temporaries are opened after the handlers are set: once one is there, the run is under way.
    int status = 0;
    const std::string stopped = stopWhileWriting(pid, dir / "out" / ".state.csv.partial", signal_number, &status, err);
    ASSERT_EQ(stopped, "") << "the runner";
    const std::string said = readAll(err);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << "; " << said;
    EXPECT_EQ(WTERMSIG(status), signal_number) << said;
    const std::string expected = std::string("rov_tether_run: stopped by ") + name + ", interrupted at t = ";
    ASSERT_EQ(said.rfind(expected, 0), 0u) << said;
    const double stopped_at = std::stod(said.substr(expected.size()));
    EXPECT_GT(stopped_at, 0.0) << said;
    EXPECT_LT(stopped_at, 4000.0) << said;  // a minute of CPU's run from its end: not a stop at the end
    EXPECT_NE(said.find("of the scenario's 5000 s: no CSV output (state, shape, vehicle, topology) was written"),
              std::string::npos)
        << said;
    EXPECT_EQ(partialFiles(dir / "out"), "");
    EXPECT_FALSE(fs::exists(dir / "out" / "shape.csv"));
    EXPECT_EQ(readAll(dir / "out" / "state.csv"), earlier);
  }
}

// rov_tether_study (the whole study: minutes of CPU) sent SIGINT, then SIGTERM, once it is writing: it removes its
// temporaries (.study.csv.partial, .stability.csv.partial), says by what it stopped, leaves an earlier run's
// study.csv and stability.csv as they were and ends by the signal. Before, it wrote both in place: a stop
// half-way left them truncated, the earlier ones lost.
TEST(StudyTool, ASignalStopsTheStudyAndLeavesTheOutputDirectoryAsItWas)
{
  const RemovedAtEnd scratch{fs::temp_directory_path() / ("rov_tether_test_study_stop_" + std::to_string(::getpid()))};
  const fs::path& dir = scratch.dir;
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const std::string err = (dir / "stderr.txt").string(), out = (dir / "out").string();
  for (const int signal_number : {SIGINT, SIGTERM})
  {
    const char* name = signal_number == SIGINT ? "SIGINT" : "SIGTERM";
    SCOPED_TRACE(name);
    std::ofstream(dir / "out" / "study.csv") << "an earlier study\n";
    std::ofstream(dir / "out" / "stability.csv") << "an earlier map\n";
    const pid_t pid = startProgram(ROV_TETHER_STUDY, {"--out", out}, err);
    ASSERT_GE(pid, 0);
    int status = 0;
    const std::string stopped = stopWhileWriting(pid, dir / "out" / ".study.csv.partial", signal_number, &status, err);
    ASSERT_EQ(stopped, "") << "the study";
    const std::string said = readAll(err);
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << "; " << said;
    EXPECT_EQ(WTERMSIG(status), signal_number) << said;
    EXPECT_EQ(said, std::string("rov_tether_study: stopped by ") + name +
                        ": study.csv and stability.csv were not written, and the output directory's earlier ones are "
                        "as they were\n");
    EXPECT_EQ(partialFiles(dir / "out"), "");
    EXPECT_EQ(readAll(dir / "out" / "study.csv"), "an earlier study\n");
    EXPECT_EQ(readAll(dir / "out" / "stability.csv"), "an earlier map\n");
  }
}

/// Looks at the run at 1 s and throws there, as a value the core refuses that no check caught would.
class ThrowingObserver : public RunObserver
{
 public:
  double nextTime() const override { return 1.0; }
  std::string observe(const Tether& /*sim*/) override { throw std::runtime_error("refused in the middle"); }
};

// A run left by an exception half-way (an observer's, here; in rov_tether_run a value the core refuses that no
// check of the scenario did, which main reports) removes its temporaries and leaves an earlier state.csv as it was.
// Before, the two .partial files stayed.
TEST(Runner, ARunLeftByAnExceptionLeavesNoTemporaryBehind)
{
  const RemovedAtEnd scratch{fs::temp_directory_path() / ("rov_tether_test_exception_" + std::to_string(::getpid()))};
  const fs::path& dir = scratch.dir;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string earlier = "an earlier run's state.csv\n";
  std::ofstream(dir / "state.csv") << earlier;
  Scenario scenario;
  ASSERT_EQ(loadScenario(std::string(ROV_TETHER_SOURCE_DIR) + "/scenarios/spool_payout.yaml", &scenario), "");
  ThrowingObserver observer;
  RunSummary summary;
  EXPECT_THROW(static_cast<void>(runScenario(scenario, dir.string(), &summary, {&observer})), std::runtime_error);
  EXPECT_EQ(partialFiles(dir), "");
  EXPECT_FALSE(fs::exists(dir / "shape.csv"));
  EXPECT_EQ(readAll(dir / "state.csv"), earlier);
}

}  // namespace
}  // namespace rov_tether::test
