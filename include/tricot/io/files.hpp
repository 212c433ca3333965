// Files: atomic writes, CSV tables, and gnuplot plots. A run never leaves a half-written file behind:
// everything is written to a temporary beside the target and renamed over it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
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

/// How a CSV cell writes a number. The default, `%.17g`, reads back as the same double; the files
/// whose numbers have a precision of their own name theirs (the DIC tables: pixels to 1e-5; the plots'
/// data: 9 digits).
struct CsvFormat {
  enum class Style { significant, decimals, shortest };
  Style style = Style::significant;
  int precision = 17;  ///< significant digits, or decimals

  static constexpr CsvFormat significant(int digits) { return {Style::significant, digits}; }
  static constexpr CsvFormat decimals(int n) { return {Style::decimals, n}; }
  /// The fewest digits that read back as the same double.
  static constexpr CsvFormat shortest() { return {Style::shortest, 0}; }
};

/// Writes CSV text row by row: cells separated by ',', each row ended by '\n'. Every CSV file tricot
/// writes is made here: to_csv's tables, the DIC tables that grow frame by frame, the plots' data.
class CsvWriter {
 public:
  /// A number in `format` (`nan`, `inf` when it is not finite).
  CsvWriter& number(double v, CsvFormat format = {});
  /// A number in `format`, or an empty cell (a missing value) when it is not finite.
  CsvWriter& number_or_empty(double v, CsvFormat format = {});
  CsvWriter& integer(long long v);
  /// A text cell: as it is, or quoted (RFC 4180: in '"', a '"' doubled) when it holds a ',', a '"' or
  /// a line break.
  CsvWriter& text(std::string_view cell);
  /// A whole row of text cells: a header.
  CsvWriter& row(const std::vector<std::string>& cells);
  /// Ends the row. A row without cells is an empty line (gnuplot's break between a surface's scans).
  CsvWriter& end_row();
  /// The text written so far, which the writer then forgets (a growing file appends it frame by frame).
  std::string take();

 private:
  void next_cell();
  std::string out_;
  bool in_row_ = false;
};

/// A numeric table with a header row. Cells are doubles.
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

/// Formats a table as CSV (CsvWriter: the header row, then `%.17g` numbers so that values round-trip).
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
