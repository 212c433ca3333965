// A verb's output folder, written as one transaction (issue 14): a run writes into a staging folder
// inside the output folder and publishes its files with renames at the end, removing the files of
// the verb's earlier run there that it did not write again. A run killed before publishing leaves
// the earlier run whole (and its own files in the hidden staging folder, which the next run
// empties); a run killed while publishing leaves a journal, which the next run into the folder
// completes before anything else. Every verb that writes a folder uses this class.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tricot::project {

class OutputDir {
 public:
  /// Opens DIR for a run of `verb` (simulate, dic, synth, experiment, identify): creates DIR,
  /// completes a publication a killed run left, and removes the staging folder DIR/.tricot-<verb>/
  /// unless `keep_staging` (identify --resume continues from the checkpoint kept there); writing a
  /// file in staging() creates it (io::write_atomic creates folders). Throws
  /// FileError when DIR is a file or cannot be created.
  /// A second run of the same verb into DIR while this one runs is refused (FileError naming DIR):
  /// the two would write and publish the same staging folder. The lock (flock on
  /// DIR/.tricot-<verb>.lock) is the kernel's, so a killed run leaves none behind.
  OutputDir(std::filesystem::path dir, std::string verb, bool keep_staging = false);
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;

  const std::filesystem::path& dir() const { return dir_; }          ///< DIR, where the files end up
  const std::filesystem::path& staging() const { return staging_; }  ///< where this run writes them

  /// Publishes the staging folder's files into DIR (renames), removes the files of the verb's earlier
  /// run that this run did not write, records this run's files in DIR/.tricot-<verb>.json and
  /// removes the staging folder. With `scope` (folder prefixes such as "tension/"), a partial run:
  /// only the earlier files under those prefixes are replaced, the others stay and stay recorded.
  /// Throws FileError when a file cannot be moved. Testing aid: with the environment variable
  /// TRICOT_TEST_KILL_BEFORE_PUBLISH set to the verb, the process kills itself (SIGKILL) first.
  void publish(const std::vector<std::string>& scope = {});

  /// The files (relative to DIR, '/'-separated) of the last run of `verb` published in DIR; empty
  /// when none was.
  static std::vector<std::string> published(const std::filesystem::path& dir, const std::string& verb);
  /// DIR/.tricot-<verb>/: the staging folder of a run of `verb` into DIR.
  static std::filesystem::path staging_of(const std::filesystem::path& dir, const std::string& verb);

 private:
  std::filesystem::path dir_, staging_;
  std::string verb_;
  int lock_ = -1;  ///< file descriptor holding the folder's lock
};

}  // namespace tricot::project
