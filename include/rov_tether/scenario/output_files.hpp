#pragma once
// Output files written under a temporary name (.NAME.partial beside it) and moved into place, all or none, only when
// the whole run succeeded: rov_tether_run's CSV files (docs/runner.md) and rov_tether_study's (docs/accuracy.md).

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace rov_tether
{

/// An output file written under a temporary name and moved into place only when the whole run succeeded.
struct OutputFile
{
  std::filesystem::path path;     ///< Where it goes.
  std::filesystem::path partial;  ///< Where it is written first.
  std::FILE* file = nullptr;      ///< Open on `partial` between openAll and closeAll.
};

/// Opens every file (creating its directory); "" or the error, with no file left behind (a directory it made stays).
std::string openAll(std::vector<OutputFile>& files);

/// Closes every file; on success (`keep`) moves them into place, all or none (a copy of an earlier file the move put
/// aside and could not remove is added to `left`), otherwise removes them. "" or the error.
std::string closeAll(std::vector<OutputFile>& files, bool keep, const std::string& out_dir,
                     std::vector<std::string>* left);

/// Closes every file without moving any into place and removes them: for a run left by an exception between
/// openAll and closeAll (the earlier outputs stay as they were).
void discardAll(std::vector<OutputFile>& files);

}  // namespace rov_tether
