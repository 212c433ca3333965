#include "tricot/io/files.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <algorithm>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "tricot/core/error.hpp"

namespace tricot::io {

namespace fs = std::filesystem;

void remove_numbered_files(const fs::path& dir, const std::string& prefix, const std::string& extension,
                           long first_stale) {
  std::error_code ec;
  for (const auto& f : fs::directory_iterator(dir, ec)) {
    const std::string name = f.path().filename().string();
    if (name.size() < prefix.size() + extension.size() + 4 || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - extension.size(), extension.size(), extension) != 0)
      continue;
    const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - extension.size());
    if (digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      continue;
    if (std::stol(digits) >= first_stale) fs::remove(f.path(), ec);
  }
}

void write_atomic(const fs::path& path, const std::string& content) {
  std::error_code ec;
  if (path.has_parent_path()) {
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw FileError({path.parent_path().string(), 0, ""}, "cannot create folder: " + ec.message());
  }
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  const fs::path tmp = path.string() + fmt::format(".tmp{:08x}", static_cast<unsigned>(rng()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw FileError({path.string(), 0, ""}, std::string("cannot write: ") + std::strerror(errno));
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      throw FileError({path.string(), 0, ""}, "write failed (disk full?)");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw FileError({path.string(), 0, ""}, "cannot move the finished file into place: " + ec.message());
  }
}

std::string read_text(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw FileError({path.string(), 0, ""}, "file not found");
  if (fs::is_directory(st)) throw FileError({path.string(), 0, ""}, "is a folder, not a file", "", "a regular file");
  if (!fs::is_regular_file(st))
    throw FileError({path.string(), 0, ""}, "not a regular file (a device, pipe or socket)", "", "a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError({path.string(), 0, ""}, std::string("cannot open the file: ") + std::strerror(errno));
  std::stringstream buf;
  buf << in.rdbuf();
  if (in.bad()) throw FileError({path.string(), 0, ""}, "read failed");
  std::string text = buf.str();
  // A UTF-8 byte-order mark (Excel and Windows editors write one) is not part of the first cell or key.
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  return text;
}

std::size_t Table::column(const std::string& name, const std::string& file) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  std::string have;
  for (const auto& c : columns) have += (have.empty() ? "" : ",") + c;
  throw InputError({file, 1, name}, "missing column", "columns " + have);
}

std::vector<double> Table::values(const std::string& name, const std::string& file) const {
  const std::size_t c = column(name, file);
  std::vector<double> v;
  v.reserve(rows.size());
  for (const auto& r : rows) v.push_back(r[c]);
  return v;
}

void CsvWriter::next_cell() {
  if (in_row_) out_ += ',';
  in_row_ = true;
}

CsvWriter& CsvWriter::number(double v, CsvFormat format) {
  next_cell();
  const auto out = std::back_inserter(out_);
  switch (format.style) {
    case CsvFormat::Style::significant: fmt::format_to(out, FMT_COMPILE("{:.{}g}"), v, format.precision); break;
    case CsvFormat::Style::decimals: fmt::format_to(out, FMT_COMPILE("{:.{}f}"), v, format.precision); break;
    case CsvFormat::Style::shortest: fmt::format_to(out, FMT_COMPILE("{}"), v); break;
  }
  return *this;
}

CsvWriter& CsvWriter::number_or_empty(double v, CsvFormat format) {
  if (std::isfinite(v)) return number(v, format);
  next_cell();
  return *this;
}

CsvWriter& CsvWriter::integer(long long v) {
  next_cell();
  fmt::format_to(std::back_inserter(out_), FMT_COMPILE("{}"), v);
  return *this;
}

CsvWriter& CsvWriter::text(std::string_view cell) {
  next_cell();
  if (cell.find_first_of(",\"\r\n") == std::string_view::npos) {
    out_ += cell;
    return *this;
  }
  out_ += '"';
  for (char c : cell) out_ += c == '"' ? std::string_view("\"\"") : std::string_view(&c, 1);
  out_ += '"';
  return *this;
}

CsvWriter& CsvWriter::row(const std::vector<std::string>& cells) {
  for (const auto& c : cells) text(c);
  return end_row();
}

CsvWriter& CsvWriter::end_row() {
  out_ += '\n';
  in_row_ = false;
  return *this;
}

std::string CsvWriter::take() {
  std::string s = std::move(out_);
  out_.clear();
  in_row_ = false;
  return s;
}

std::string to_csv(const Table& t) {
  CsvWriter csv;
  csv.row(t.columns);
  for (const auto& r : t.rows) {
    for (double v : r) csv.number(v);
    csv.end_row();
  }
  return csv.take();
}

namespace {
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r");
    const auto e = cell.find_last_not_of(" \t\r");
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}
}  // namespace

Table read_csv(const fs::path& path) {
  const std::string text = read_text(path);
  const std::string file = path.string();
  Table t;
  std::istringstream in(text);
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    auto cells = split(line);
    if (t.columns.empty()) {
      t.columns = cells;
      continue;
    }
    if (cells.size() != t.columns.size())
      throw InputError({file, line_no, ""}, "wrong number of cells", std::to_string(cells.size()),
                       std::to_string(t.columns.size()) + " as in the header");
    std::vector<double> row(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const char* b = cells[i].c_str();
      char* e = nullptr;
      row[i] = std::strtod(b, &e);
      if (cells[i].empty() || *e != '\0' || !std::isfinite(row[i]))
        throw InputError({file, line_no, t.columns[i]}, "not a finite number", "\"" + cells[i] + "\"",
                         "a finite number");
    }
    t.rows.push_back(std::move(row));
    t.lines.push_back(line_no);
  }
  if (t.columns.empty()) throw InputError({file, 0, ""}, "empty file: no header row");
  return t;
}

std::string gnuplot_quote(const fs::path& p) {
  std::string q = "'";
  for (char c : p.string()) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

bool run_gnuplot(const std::string& script, std::string* why) {
  // gnuplot's messages go to a temporary file, never to our stdout: on failure the first line that
  // names the problem becomes `why`.
  // The script goes through a file too, not a pipe: a gnuplot that is missing or stops early would
  // leave our write to a closed pipe, and SIGPIPE would end the run.
  char log_name[] = "/tmp/tricot-gnuplot-XXXXXX";
  char script_name[] = "/tmp/tricot-gnuplot-XXXXXX";
  const int fd = mkstemp(log_name);
  const int sd = fd < 0 ? -1 : mkstemp(script_name);
  if (fd < 0 || sd < 0) {
    if (fd >= 0) close(fd), std::remove(log_name);
    if (why) *why = std::string("cannot make a temporary file for gnuplot: ") + std::strerror(errno);
    return false;
  }
  close(fd);
  const bool written = ::write(sd, script.data(), script.size()) == static_cast<ssize_t>(script.size());
  close(sd);
  const int rc =
      written ? std::system(fmt::format("gnuplot '{}' >'{}' 2>&1 </dev/null", script_name, log_name).c_str()) : -1;
  std::remove(script_name);
  std::string output;
  {
    std::ifstream in(log_name);
    std::stringstream buf;
    buf << in.rdbuf();
    output = buf.str();
  }
  std::remove(log_name);
  if (rc == 0) return true;
  if (why) {
    if (WIFEXITED(rc) && WEXITSTATUS(rc) == 127) {
      *why = "gnuplot is not installed (apt install gnuplot-nox)";
    } else {
      std::string first;
      std::istringstream in(output);
      for (std::string line; std::getline(in, line);) {
        const auto b = line.find_first_not_of(" \t^");
        if (b == std::string::npos) continue;
        first = line.substr(b);
        if (line.find("rror") != std::string::npos || line.find("line ") != std::string::npos) break;
      }
      *why = "gnuplot failed" + (first.empty() ? std::string() : ": " + first);
    }
  }
  return false;
}

}  // namespace tricot::io
