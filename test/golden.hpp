#pragma once
// Golden outputs: hashes of whole output files, compared with the values committed in test/golden/.
// They pin behaviour through refactoring: a change that moves outputs on purpose regenerates them with
//   ROV_TETHER_UPDATE_GOLDEN=1 test_core --gtest_filter='Golden*'        (test/golden/runner*.txt)
//   ROV_TETHER_UPDATE_GOLDEN=1 test_ros_layer --gtest_filter='Golden*'   (test/golden/node_replay.txt)
// and commits the new file on its own, saying why the outputs moved. Update in one process, as above: tests that
// share a file (GoldenFile's scope) each rewrite it whole, so shards run side by side would undo each other.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>

namespace rov_tether::test
{

/// FNV-1a, 64 bit: enough to tell two outputs apart, no dependency.
inline std::uint64_t fnv1a(const std::string& bytes, std::uint64_t hash = 0xcbf29ce484222325ULL)
{
  for (unsigned char c : bytes)
  {
    hash = (hash ^ c) * 0x100000001b3ULL;
  }
  return hash;
}

inline std::string hex(std::uint64_t value)
{
  std::ostringstream out;
  out << std::hex;
  out.width(16);
  out.fill('0');
  out << value;
  return out.str();
}

inline std::string readFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

/// A file of "key hash" lines under test/golden/. Compares each computed hash with the committed one;
/// with ROV_TETHER_UPDATE_GOLDEN=1 set, writes the computed ones instead (when the test finishes).
/// A test may own only the keys that contain `scope` (one of several tests sharing the file, each one run
/// of the suite's shards): it checks and rewrites those, and leaves the others as they are.
class GoldenFile
{
 public:
  explicit GoldenFile(const std::string& name, std::string scope = "")
      : path_(std::string(ROV_TETHER_SOURCE_DIR) + "/test/golden/" + name),
        scope_(std::move(scope)),
        update_(std::getenv("ROV_TETHER_UPDATE_GOLDEN") != nullptr)
  {
    std::istringstream in(readFile(path_));
    std::string key, value;
    while (in >> key >> value)
    {
      (key.find(scope_) != std::string::npos ? expected_ : others_)[key] = value;
    }
  }
  ~GoldenFile()
  {
    // Written only from a complete, passing run: a test that stopped early would drop hashes silently.
    if (update_ && !::testing::Test::HasFailure() && computed_.size() >= expected_.size())
    {
      std::map<std::string, std::string> all = others_;
      all.insert(computed_.begin(), computed_.end());
      std::ofstream out(path_);
      for (const auto& [key, value] : all)
      {
        out << key << ' ' << value << '\n';
      }
    }
  }
  GoldenFile(const GoldenFile&) = delete;
  GoldenFile& operator=(const GoldenFile&) = delete;

  void check(const std::string& key, std::uint64_t hash)
  {
    ASSERT_NE(key.find(scope_), std::string::npos) << key << " is outside this test's scope '" << scope_ << "'";
    computed_[key] = hex(hash);
    if (update_)
    {
      return;
    }
    const auto it = expected_.find(key);
    ASSERT_NE(it, expected_.end()) << "no golden hash for " << key << " in " << path_
                                   << " (new case? regenerate with ROV_TETHER_UPDATE_GOLDEN=1)";
    EXPECT_EQ(it->second, hex(hash)) << key << ": output differs from the golden one; if the change is "
                                     << "deliberate, regenerate " << path_ << " in its own commit and say why";
  }
  /// Every committed hash was checked (call at the end of a test): a case that stops running is a change.
  void expectAllChecked() const
  {
    for (const auto& [key, value] : expected_)
    {
      EXPECT_EQ(computed_.count(key), 1u) << key << " is in the golden file but was not computed";
    }
  }

 private:
  std::string path_;
  std::string scope_;  ///< the keys this test owns contain it ("": all)
  bool update_;
  std::map<std::string, std::string> expected_;  ///< the committed hashes in scope
  std::map<std::string, std::string> others_;    ///< the committed hashes of the file's other tests
  std::map<std::string, std::string> computed_;
};

}  // namespace rov_tether::test
