#include "tricot/io/log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <regex>

#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"
#include "tricot/io/files.hpp"

namespace tricot::io {

namespace {

std::string_view trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\"");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\"");
  return s.substr(b, e - b + 1);
}

/// The cells of a line (trimmed views into it); trailing empty cells dropped.
void split_cells(std::string_view line, char delimiter, std::vector<std::string_view>& cells) {
  cells.clear();
  std::size_t start = 0;
  for (;;) {
    const auto end = line.find(delimiter, start);
    cells.push_back(trim(line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  while (cells.size() > 1 && cells.back().empty()) cells.pop_back();  // LabVIEW ends rows with a tab
}

std::vector<std::string> split_cells(std::string_view line, char delimiter) {
  std::vector<std::string_view> views;
  split_cells(line, delimiter, views);
  return {views.begin(), views.end()};
}

/// Parses a whole cell as a number (NaN and inf included: they are numbers that are not finite).
bool parse_number(std::string_view cell, bool decimal_comma, double& v) {
  if (cell.empty() || cell.size() > 64) return false;
  char buffer[64];
  std::size_t n = 0;
  for (char ch : cell) buffer[n++] = decimal_comma && ch == ',' ? '.' : ch;
  const char* b = buffer;
  const char* e = buffer + n;
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

struct Line {
  int number;  // 1-based
  std::string_view text;
};

std::vector<Line> split_lines(std::string_view text) {
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<Line> lines;
  int n = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++n;
    std::string_view l = text.substr(start, end - start);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    lines.push_back({n, l});
    start = end + 1;
  }
  while (!lines.empty() && trim(lines.back().text).empty()) lines.pop_back();
  return lines;
}

bool blank(std::string_view s) { return trim(s).empty(); }

enum class RowKind { text, data };
template <class Cells>
RowKind kind(const Cells& cells, bool decimal_comma) {
  double v;
  for (const auto& c : cells)
    if (parse_number(c, decimal_comma, v)) return RowKind::data;
  return RowKind::text;
}

}  // namespace

void LogFormat::validate() const {
  if (delimiter != 0 && delimiter != ',' && delimiter != ';' && delimiter != '\t')
    throw InputError({"", 0, "log.delimiter"}, "not a delimiter", std::string(1, delimiter), "',', ';' or tab");
  if (header_line < 0)
    throw InputError({"", 0, "log.header_line"}, "out of range", std::to_string(header_line), "≥ 0 (0 = detect)");
}

std::pair<std::string, std::string> split_unit(std::string_view header) {
  std::string_view h = trim(header);
  for (auto [open, close] : {std::pair{'[', ']'}, std::pair{'(', ')'}}) {
    const auto o = h.rfind(open);
    const auto c = h.rfind(close);
    if (o != std::string_view::npos && c != std::string_view::npos && c > o && trim(h.substr(c + 1)).empty())
      return {std::string(trim(h.substr(0, o))), std::string(trim(h.substr(o + 1, c - o - 1)))};
  }
  return {std::string(h), ""};
}

std::string column_key(std::string_view name) {
  const std::string bare = split_unit(name).first;
  std::string key;
  for (unsigned char ch : bare)
    if (std::isalnum(ch)) key += static_cast<char>(std::tolower(ch));
  return key;
}

LogTable parse_log(std::string_view text, const std::string& file, const LogFormat& format) {
  format.validate();
  const std::vector<Line> lines = split_lines(text);
  LogTable t;
  t.file = file;
  t.format = format;

  // Delimiter and decimal mark, from the last rows (data; the metadata above may use anything).
  std::vector<const Line*> tail;
  for (auto it = lines.rbegin(); it != lines.rend() && tail.size() < 50; ++it)
    if (!blank(it->text)) tail.push_back(&*it);
  if (tail.empty()) throw InputError({file, 0, ""}, "empty log: no header and no data");
  auto share = [&](char c) {
    return std::count_if(tail.begin(), tail.end(), [c](const Line* l) { return l->text.find(c) != std::string::npos; });
  };
  if (format.delimiter == 0) {
    const auto half = static_cast<long>(tail.size() + 1) / 2;
    t.format.delimiter = share('\t') >= half ? '\t' : share(';') >= half ? ';' : ',';
    // a decimal comma: some cell of the last rows is a number once its comma is read as a point
    t.format.decimal_comma = false;
    double v;
    if (t.format.delimiter != ',')
      for (const Line* l : tail)
        for (const auto& c : split_cells(l->text, t.format.delimiter))
          if (c.find(',') != std::string::npos && parse_number(c, true, v)) t.format.decimal_comma = true;
  }
  const char d = t.format.delimiter;
  const bool dc = t.format.decimal_comma;

  // Header: given, or the first all-text row followed by data rows with as many cells.
  std::size_t header = lines.size();
  if (format.header_line > 0) {
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (lines[i].number == format.header_line) header = i;
    if (header == lines.size())
      throw InputError({file, format.header_line, "log.header_line"}, "the log has no such line",
                       std::to_string(format.header_line), "1 to " + std::to_string(lines.size()));
  } else {
    std::vector<std::size_t> rows;  // indices of non-blank lines
    for (std::size_t i = 0; i < lines.size(); ++i)
      if (!blank(lines[i].text)) rows.push_back(i);
    // The header is the all-text row followed by the longest run of data rows with as many cells
    // (metadata lines are short runs; a run ends at the next all-text row of that width).
    std::vector<std::pair<bool, std::size_t>> shape(rows.size());  // (is data, cell count) per row
    std::vector<std::string_view> cells;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      split_cells(lines[rows[r]].text, d, cells);
      shape[r] = {kind(cells, dc) == RowKind::data, cells.size()};
    }
    std::size_t best = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      if (shape[r].first) continue;
      std::size_t run = 0;
      for (std::size_t k = r + 1; k < rows.size(); ++k) {
        if (shape[k].second != shape[r].second) continue;
        if (!shape[k].first) break;
        ++run;
      }
      if (run > best) best = run, header = rows[r];
    }
    if (header == lines.size() && !rows.empty() &&
        std::none_of(shape.begin(), shape.end(), [](const auto& x) { return x.first; }))
      throw InputError({file, lines[rows.back()].number, ""}, "no data rows: every line is text (a header alone?)", "",
                       "rows of numbers below the header");
    if (header == lines.size())
      throw InputError(
          {file, 0, ""}, "no header row found", "",
          std::string("a row of column names followed by rows of numbers separated by ") + (d == '\t'  ? "tabs"
                                                                                            : d == ';' ? "';'"
                                                                                                       : "','"));
  }
  for (std::size_t i = 0; i < header; ++i) t.metadata.emplace_back(lines[i].text);
  t.columns = split_cells(lines[header].text, d);
  for (const auto& c : t.columns) t.units.push_back(split_unit(c).second);
  const std::size_t nc = t.columns.size();
  t.values_.assign(nc, {});
  t.text_.assign(nc, {});
  std::vector<std::string_view> cells;
  std::vector<std::size_t> first_text(nc, std::string::npos);  // row of a column's first non-number
  for (std::size_t i = header + 1; i < lines.size(); ++i) {
    if (blank(lines[i].text)) continue;
    split_cells(lines[i].text, d, cells);
    if (cells.size() > nc)
      throw InputError({file, lines[i].number, ""}, "more cells than the header has columns",
                       std::to_string(cells.size()), std::to_string(nc));
    const std::size_t row = t.lines.size();
    for (std::size_t c = 0; c < nc; ++c) {
      const std::string_view cell = c < cells.size() ? cells[c] : std::string_view{};
      double v;
      if (!parse_number(cell, dc, v) || !std::isfinite(v)) {
        v = std::numeric_limits<double>::quiet_NaN();
        if (first_text[c] == std::string::npos) first_text[c] = row;
      }
      t.values_[c].push_back(v);
    }
    t.lines.push_back(lines[i].number);
  }
  // The text of the columns that hold some non-number: a second pass over those columns only.
  for (std::size_t c = 0; c < nc; ++c)
    if (first_text[c] != std::string::npos) t.text_[c].reserve(t.lines.size());
  if (std::any_of(first_text.begin(), first_text.end(), [](std::size_t r) { return r != std::string::npos; }))
    for (std::size_t i = header + 1; i < lines.size(); ++i) {
      if (blank(lines[i].text)) continue;
      split_cells(lines[i].text, d, cells);
      for (std::size_t c = 0; c < nc; ++c)
        if (first_text[c] != std::string::npos)
          t.text_[c].emplace_back(c < cells.size() ? cells[c] : std::string_view{});
    }
  if (t.lines.empty()) throw InputError({file, lines[header].number, ""}, "the log has a header but no data rows");
  return t;
}

LogTable read_log(const std::filesystem::path& path, const LogFormat& format) {
  return parse_log(read_text(path), path.string(), format);
}

std::size_t LogTable::column(std::string_view name) const {
  const std::string key = column_key(name);
  std::vector<std::size_t> found;
  for (std::size_t c = 0; c < columns.size(); ++c)
    if (column_key(columns[c]) == key) found.push_back(c);
  if (found.size() == 1) return found[0];
  std::string list;
  for (const auto& c : columns) list += (list.empty() ? "" : ", ") + ("'" + c + "'");
  if (found.size() > 1)
    throw InputError({file, 0, std::string(name)}, "several columns match this name", "", "one of " + list);
  Strings keys;
  for (const auto& c : columns) keys.push_back(column_key(c));
  const std::string hint = closest_name(key, keys);
  std::string problem = "no such column in the log";
  if (!hint.empty())
    problem += "; did you mean '" + columns[std::find(keys.begin(), keys.end(), hint) - keys.begin()] + "'?";
  throw InputError({file, 0, std::string(name)}, problem, "", "one of " + list);
}

bool LogTable::has_column(std::string_view name) const {
  const std::string key = column_key(name);
  return std::any_of(columns.begin(), columns.end(), [&](const std::string& c) { return column_key(c) == key; });
}

std::vector<double> LogTable::numbers(std::string_view name) const {
  const std::size_t c = column(name);
  if (!text_[c].empty())
    for (std::size_t r = 0; r < rows(); ++r)
      if (!std::isfinite(values_[c][r])) {
        const std::string& cell = text_[c][r];
        throw InputError({file, lines[r], columns[c]}, cell.empty() ? "empty cell" : "not a finite number",
                         "\"" + cell + "\"", "a finite number");
      }
  return values_[c];
}

std::vector<double> LogTable::numbers_or_empty(std::string_view name) const {
  const std::size_t c = column(name);
  if (!text_[c].empty())
    for (std::size_t r = 0; r < rows(); ++r)
      if (!std::isfinite(values_[c][r]) && !text_[c][r].empty())
        throw InputError({file, lines[r], columns[c]}, "not a finite number", "\"" + text_[c][r] + "\"",
                         "a finite number, or an empty cell for a missing value");
  return values_[c];
}

std::vector<double> LogTable::times(std::string_view name) const {
  std::vector<double> t = numbers(name);
  const std::size_t c = column(name);
  for (std::size_t r = 1; r < t.size(); ++r)
    if (!(t[r] > t[r - 1]))
      throw InputError({file, lines[r], columns[c]}, t[r] < t[r - 1] ? "time goes backwards" : "time repeats",
                       format_number(t[r]),
                       "> " + format_number(t[r - 1]) + " (line " + std::to_string(lines[r - 1]) + ")");
  return t;
}

std::vector<std::string> LogTable::text(std::string_view name) const {
  const std::size_t c = column(name);
  if (!text_[c].empty()) return text_[c];
  std::vector<std::string> out;
  out.reserve(rows());
  for (double v : values_[c]) out.push_back(fmt::format("{:.17g}", v));
  return out;
}

std::string to_log_text(const LogWriter& log) {
  const char* eol = log.crlf ? "\r\n" : "\n";
  std::string s;
  for (const auto& m : log.metadata) s += m + eol;
  for (std::size_t c = 0; c < log.columns.size(); ++c) s += (c ? std::string(1, log.delimiter) : "") + log.columns[c];
  s += eol;
  const std::size_t n = log.columns_data.empty() ? 0 : log.columns_data[0].size();
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < log.columns_data.size(); ++c) {
      std::string v = fmt::format("{:.{}g}", log.columns_data[c][r], log.digits);
      if (log.decimal_comma) std::replace(v.begin(), v.end(), '.', ',');
      s += (c ? std::string(1, log.delimiter) : "") + v;
    }
    s += eol;
  }
  return s;
}

std::vector<FrameTime> read_camera_log(const std::filesystem::path& path, std::string_view file_column,
                                       std::string_view time_column, const LogFormat& format) {
  const LogTable t = read_log(path, format);
  const std::vector<std::string> files = t.text(file_column);
  const std::vector<double> times = t.times(time_column);
  std::vector<FrameTime> frames(files.size());
  for (std::size_t r = 0; r < files.size(); ++r) {
    if (files[r].empty()) throw InputError({t.file, t.lines[r], t.columns[t.column(file_column)]}, "empty file name");
    frames[r] = {files[r], times[r]};
  }
  return frames;
}

std::string to_camera_log_text(const std::vector<FrameTime>& frames) {
  CsvWriter csv;
  csv.row({"file", "time [s]"});
  for (const auto& f : frames) csv.text(f.file).number(f.time, CsvFormat::decimals(6)).end_row();
  return csv.take();
}

double time_from_file_name(const std::string& file_name) {
  const std::string stem = std::filesystem::path(file_name).stem().string();
  static const std::regex number(R"(([0-9]+(?:[.,][0-9]+)?)\s*(ms|s)(?![a-zA-Z]))");
  double t = 0;
  bool found = false;
  for (auto it = std::sregex_iterator(stem.begin(), stem.end(), number); it != std::sregex_iterator(); ++it) {
    std::string v = (*it)[1].str();
    std::replace(v.begin(), v.end(), ',', '.');
    t = std::stod(v) * ((*it)[2].str() == "ms" ? 1e-3 : 1.0);
    found = true;
  }
  if (!found)
    throw InputError({file_name, 0, ""}, "no time in the file name", stem,
                     "a number followed by s or ms, as in img_0003_t1.500s.tif");
  return t;
}

}  // namespace tricot::io
