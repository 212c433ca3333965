// Files: atomic writes, CSV tables, and gnuplot plots. A run never leaves a half-written file behind:
// everything is written to a temporary beside the target and renamed over it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace tricot::io {

/// Writes `content` to `path` atomically (temp file in the same folder + rename). Creates parent
/// folders. Throws FileError when the folder cannot be created or the file cannot be written.
void write_atomic(const std::filesystem::path& path, const std::string& content);

/// Reads a whole text file. Throws FileError naming the file when it cannot be read.
std::string read_text(const std::filesystem::path& path);

/// Removes the files of `dir` named `prefix` + a number of 4 or more digits + `extension` whose number
/// is ≥ `first_stale`: what an earlier, longer run left beyond this run's series (step_NNNN.vtu,
/// frame_NNNN.png), which a glob would otherwise take for this run's. Errors are ignored.
void remove_numbered_files(const std::filesystem::path& dir, const std::string& prefix, const std::string& extension,
                           long first_stale);

/// A numeric table with a header row. Cells are doubles; `text` holds columns that are words.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  /// read_csv: the 1-based line of each row in its file, for messages (empty otherwise).
  std::vector<int> lines;

  /// Index of a column; throws InputError naming the file and the missing column.
  std::size_t column(const std::string& name, const std::string& file = {}) const;
  /// Copy of one column.
  std::vector<double> values(const std::string& name, const std::string& file = {}) const;
};

/// Formats a table as CSV (header row, then `%.17g` numbers so that values round-trip).
std::string to_csv(const Table& t);
/// Reads a CSV table of numbers with a header row. Empty lines and lines starting with '#' are
/// skipped. Throws FileError when unreadable, InputError with FILE:LINE: COLUMN for a cell that is
/// not a finite number (NaN included) or a row of the wrong length.
Table read_csv(const std::filesystem::path& path);

/// Runs gnuplot on `script` (which must `set output` itself). Returns false, with a reason in
/// `why`, when gnuplot is not installed or fails; plots are a convenience, never a reason to fail a run.
bool run_gnuplot(const std::string& script, std::string* why = nullptr);

/// A path as a gnuplot string literal ('…', quotes doubled), for the scripts given to run_gnuplot.
std::string gnuplot_quote(const std::filesystem::path& p);

}  // namespace tricot::io
