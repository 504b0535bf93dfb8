// The runner's output files: see output_files.hpp.
#include "rov_tether/scenario/output_files.hpp"

#include <system_error>

namespace rov_tether
{
namespace
{

namespace fs = std::filesystem;

/// Where the earlier file at `path` is kept while the new outputs move into place (moveIntoPlace).
fs::path asideOf(const fs::path& path) { return path.parent_path() / ("." + path.filename().string() + ".earlier"); }

/// "" or the error naming a file already at a name an earlier output would be moved aside to: it can only be an
/// earlier file of a run that stopped while it moved its outputs into place, maybe the only copy of it, which a move
/// aside would overwrite.
std::string asideInTheWay(const std::vector<OutputFile>& files)
{
  for (const OutputFile& out : files)
  {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(asideOf(out.path), ec)))
    {
      return "cannot write '" + out.path.string() + "': '" + asideOf(out.path).string() +
             "' is in the way: an earlier output moved aside, by a run that stopped before it had moved its own "
             "into place (then it may be the only copy of the earlier one: put it back) or by a run that could not "
             "remove it once its own were in place (then it is the replaced one, older than '" +
             out.path.filename().string() + "': delete it)";
    }
  }
  return "";
}

/// Moves every CSV file into place, all or nothing: a failure half-way left some new files and some earlier ones
/// in the directory, and no word of which. First each earlier file at a target (any entry but a directory, which
/// the rename of a file cannot replace) is moved aside to .<name>.earlier beside it, then each new file is moved in,
/// then the earlier files are removed. Should a move fail, what was done is undone (each earlier file moved back
/// over this run's, this run's removed where there was none), so that every one of these files is as it was before
/// the run, and the error says so; should the undoing fail too, the error names each file it leaves otherwise. A
/// copy moved aside that cannot be removed once all are in place is added to `left` (its path and why), for the
/// run's warnings. "" or the error; every partial file is gone either way.
std::string moveIntoPlace(const std::vector<OutputFile>& files, const fs::path& out_dir, std::vector<std::string>* left)
{
  std::string error = asideInTheWay(files);  // openAll's check, again: one may have come since
  std::vector<bool> aside(files.size(), false);
  for (std::size_t i = 0; i < files.size() && error.empty(); ++i)
  {
    std::error_code ec;
    const fs::file_status status = fs::symlink_status(files[i].path, ec);
    if (fs::exists(status) && !fs::is_directory(status))
    {
      fs::rename(files[i].path, asideOf(files[i].path), ec);
      aside[i] = !ec;
      error = ec ? "cannot move the earlier '" + files[i].path.string() + "' aside: " + ec.message() : "";
    }
  }
  std::size_t moved = 0;  // files[0 .. moved) are in place
  for (; moved < files.size() && error.empty(); ++moved)
  {
    std::error_code ec;
    fs::rename(files[moved].partial, files[moved].path, ec);
    if (ec)
    {
      error = "cannot move '" + files[moved].path.string() + "' into place: " + ec.message();
      break;
    }
  }
  if (error.empty())
  {
    for (std::size_t i = 0; i < files.size(); ++i)
    {
      std::error_code ec;
      if (aside[i])
      {
        fs::remove(asideOf(files[i].path), ec);
      }
      if (ec)
      {
        left->push_back(asideOf(files[i].path).lexically_relative(out_dir).string() + " (" + ec.message() + ")");
      }
    }
    return "";
  }
  // The undoing: every earlier file back, this run's removed where there was none, the partial files not moved in.
  std::string not_undone;
  for (std::size_t i = 0; i < files.size(); ++i)
  {
    const std::string path = files[i].path.string(), earlier = asideOf(files[i].path).string();
    std::error_code ec;
    if (aside[i])
    {
      fs::rename(earlier, path, ec);  // over this run's file, if it was moved in
      not_undone += ec ? "; '" + path + "' is " + (i < moved ? "this run's" : "missing") + ", the earlier one is '" +
                             earlier + "' (" + ec.message() + ")"
                       : "";
    }
    else if (i < moved)
    {
      fs::remove(path, ec);
      not_undone += ec ? "; '" + path + "' is this run's, where there was none (" + ec.message() + ")" : "";
    }
    fs::remove(files[i].partial, ec);
  }
  return error + (not_undone.empty() ? ". No CSV output was replaced: every CSV file is as it was before this run"
                                     : ". Undoing the moves failed, so the directory holds a mix" + not_undone +
                                           "; every other CSV file is as it was before this run");
}

}  // namespace

/// Opens every file (creating its directory); "" or the error, with nothing left behind.
std::string openAll(std::vector<OutputFile>& files)
{
  std::error_code ec;
  for (const OutputFile& out : files)
  {
    if (fs::is_directory(out.path, ec))
    {
      return "cannot write '" + out.path.string() + "': it is a directory";
    }
  }
  const std::string aside_error = asideInTheWay(files);
  if (!aside_error.empty())
  {
    return aside_error;
  }
  for (OutputFile& out : files)
  {
    fs::create_directories(out.path.parent_path(), ec);
    if (!ec)
    {
      out.partial = out.path.parent_path() / ("." + out.path.filename().string() + ".partial");
      out.file = std::fopen(out.partial.c_str(), "w");
    }
    if (out.file == nullptr)
    {
      discardAll(files);  // the files opened before this one: nothing left behind
      return ec ? "cannot create output directory '" + out.path.parent_path().string() + "': " + ec.message()
                : "cannot write in '" + out.path.parent_path().string() + "'";
    }
  }
  return "";
}

void discardAll(std::vector<OutputFile>& files)
{
  for (OutputFile& out : files)
  {
    if (out.file != nullptr)
    {
      std::fclose(out.file);
      out.file = nullptr;
    }
    std::error_code ec;
    fs::remove(out.partial, ec);
  }
}

/// Closes every file; on success (`keep`) moves them into place (moveIntoPlace: all or none), otherwise removes
/// them. "" or the error.
std::string closeAll(std::vector<OutputFile>& files, bool keep, const std::string& out_dir,
                     std::vector<std::string>* left)
{
  bool written = keep;
  for (OutputFile& out : files)
  {
    written = std::ferror(out.file) == 0 && written;
    written = std::fclose(out.file) == 0 && written;
    out.file = nullptr;  // closed: a discardAll after this closes nothing twice
  }
  if (!written)
  {
    for (OutputFile& out : files)
    {
      std::error_code ec;
      fs::remove(out.partial, ec);
    }
    return "error while writing in '" + out_dir + "'";
  }
  return moveIntoPlace(files, out_dir, left);
}

}  // namespace rov_tether
