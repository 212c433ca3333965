// Acquisition logs: the delimited tables that a load cell's acquisition program (LabVIEW, a testing
// machine's software) and a camera write (docs/theory.md §1, the experimental branch). A lab engineer's
// files are read as they come:
//   - comma-, semicolon- or tab-separated (detected from the data rows);
//   - metadata lines before the header (the header is the last all-text row with as many cells as
//     the first data row that follows it);
//   - decimal comma (French, German locales: detected when the delimiter is not ',');
//   - units in the header (`Force [N]`, `Time (s)`), CRLF line ends, a UTF-8 byte-order mark.
// Columns are chosen by name, ignoring case, units and punctuation; an unknown name gets a
// did-you-mean. Every bad cell is reported with FILE:LINE: COLUMN.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace tricot::io {

/// How the columns of a log are separated and how its numbers are written. 0 = detect.
struct LogFormat {
  char delimiter = 0;          ///< ',', ';', '\t' or 0 = detect (tab, else ';', else ',')
  bool decimal_comma = false;  ///< numbers written 1,25 (set by detection; honoured when given with `delimiter`)
  int header_line = 0;         ///< 1-based line of the header row, 0 = detect

  /// Throws InputError naming `log.delimiter` / `log.header_line` when out of range.
  void validate() const;
};

/// A log read as columns of numbers (and, for columns holding words, their text).
class LogTable {
 public:
  std::string file;                   ///< as given, for messages
  std::vector<std::string> metadata;  ///< the lines before the header, as written (BOM and CR removed)
  std::vector<std::string> columns;   ///< header cells as written ("Force [N]")
  std::vector<std::string> units;     ///< the unit of each column ("N"), "" when the header gives none
  std::vector<int> lines;             ///< 1-based line of each data row
  LogFormat format;                   ///< what was detected (or given)

  std::size_t rows() const { return lines.size(); }
  /// The column whose name matches `name` ignoring case, units and punctuation (`force`, `Force [N]`,
  /// `FORCE(N)` all match `Force [N]`). Throws InputError (key = name) when none does, with a
  /// did-you-mean and the list of columns, or when two columns match.
  std::size_t column(std::string_view name) const;
  /// True when some column matches `name`.
  bool has_column(std::string_view name) const;
  /// The numbers of a column. Throws InputError FILE:LINE: COLUMN at the first cell that is not a
  /// finite number (text, empty, NaN, inf).
  std::vector<double> numbers(std::string_view name) const;
  /// numbers() where an empty cell is a missing value, NaN (a point a DIC tool lost in that frame);
  /// InputError FILE:LINE: COLUMN at a cell that holds text, NaN or inf.
  std::vector<double> numbers_or_empty(std::string_view name) const;
  /// numbers(), which must also increase strictly down the column (a time): the error names the
  /// first line where it goes backwards or repeats.
  std::vector<double> times(std::string_view name) const;
  /// The cells of a column: as written (trimmed) in a column that holds some word, empty cell or
  /// NaN; re-formatted (`%.17g`) in a column of finite numbers only.
  std::vector<std::string> text(std::string_view name) const;

 private:
  friend LogTable parse_log(std::string_view, const std::string&, const LogFormat&);
  // Numbers are parsed once (a 1 kHz log of an hour has millions of cells): per column, its values
  // (NaN where a cell is not a finite number) and, only for columns with such cells, every cell's text.
  std::vector<std::vector<double>> values_;
  std::vector<std::vector<std::string>> text_;
};

/// The key a column name is matched by: lowercase letters and digits only, units in [...] or (...)
/// removed (`Cross-head [mm]` → `crosshead`).
std::string column_key(std::string_view name);
/// Splits `Force [N]` / `Time (s)` into the name and the unit ("N"); the unit is "" when none.
std::pair<std::string, std::string> split_unit(std::string_view header);

/// Parses a log's text; `file` stands for the file in messages. Throws InputError for no header, no
/// data, or a row with more cells than the header (naming its line).
LogTable parse_log(std::string_view text, const std::string& file, const LogFormat& format = {});
/// Reads a log file. Throws FileError when it cannot be read, then as parse_log.
LogTable read_log(const std::filesystem::path& path, const LogFormat& format = {});

/// A log to write: metadata lines, then a header, then rows of numbers.
struct LogWriter {
  std::vector<std::string> metadata;              ///< written first, one per line, as given
  std::vector<std::string> columns;               ///< header cells, units included ("Force [N]")
  std::vector<std::vector<double>> columns_data;  ///< per column, all the same length
  char delimiter = '\t';
  bool decimal_comma = true;  ///< write 1,25 (a French LabVIEW)
  bool crlf = true;           ///< Windows line ends
  int digits = 6;             ///< significant digits
};
/// The text of the log (what a LabVIEW acquisition on a French Windows PC writes by default).
std::string to_log_text(const LogWriter& log);

/// One image of a sequence and the time the camera gave it.
struct FrameTime {
  std::string file;
  double time = 0;  ///< s, camera clock
};
/// A camera log: a table with a file-name column and a time column (names matched as in
/// LogTable::column). Times must increase strictly (the error names the line).
std::vector<FrameTime> read_camera_log(const std::filesystem::path& path, std::string_view file_column = "file",
                                       std::string_view time_column = "time", const LogFormat& format = {});

/// A camera log's text: a `file,time [s]` CSV header, then one row per image (times to the µs).
std::string to_camera_log_text(const std::vector<FrameTime>& frames);

/// The time written in an image's file name: the last number followed by `s` or `ms`
/// (`img_0003_t1.500s.tif` → 1.5, `cam-12500ms.png` → 12.5), a decimal comma allowed. Throws
/// InputError naming the file when the name holds no time.
double time_from_file_name(const std::string& file_name);

}  // namespace tricot::io
