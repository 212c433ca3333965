// The lab report (issue 13): a small document model — a title, sections of paragraphs, key/value
// tables, numeric tables, PNG figures and correlation heat maps — written as one self-contained
// DIR/report.html (figures as base64 data URIs, inline CSS with an A4 print stylesheet, no external
// resource) and DIR/report.json holding every number and text shown. Any pipeline adds what it has
// with one call: `doc.section(report::kSync).figure(dir / "plots/sync.png", "…")`. Sections appear
// in the canonical order of kSectionOrder, whatever order they were added in, and only when present.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace tricot::project::report {

/// Canonical section ids, in the order the report shows them (the titles are the caller's).
inline constexpr const char* kInputs = "inputs";
inline constexpr const char* kDic = "dic";
inline constexpr const char* kSync = "sync";
inline constexpr const char* kHistory = "history";
inline constexpr const char* kCoefficients = "coefficients";
inline constexpr const char* kCorrelation = "correlation";
inline constexpr const char* kSurfaces = "surfaces";
inline constexpr const char* kEq9 = "eq9";
inline constexpr const char* kIdentifiability = "identifiability";
inline constexpr const char* kFit = "fit";
inline constexpr const char* kTiming = "timing";
inline const std::vector<std::string> kSectionOrder{
    kInputs, kDic, kSync, kHistory, kCoefficients, kCorrelation, kSurfaces, kEq9, kIdentifiability, kFit, kTiming};

/// A cell of a key/value table: text, or a number shown with `digits` significant digits.
struct Value {
  std::variant<std::string, double> v;
  int digits = 6;
  std::string unit;  ///< appended after the number ("s", "N/mm"); part of the text, not of the JSON number

  Value(std::string s) : v(std::move(s)) {}
  Value(const char* s) : v(std::string(s)) {}
  Value(double x, int digits_ = 6, std::string unit_ = {}) : v(x), digits(digits_), unit(std::move(unit_)) {}
  Value(int x) : v(double(x)) {}
  Value(long x) : v(double(x)) {}
  Value(bool b) : v(std::string(b ? "yes" : "no")) {}
  bool is_number() const { return std::holds_alternative<double>(v); }
};

struct Paragraph {
  enum class Style { body, note, callout };
  std::string text;
  Style style = Style::body;  ///< note: a smaller, grey remark; callout: a boxed key result
};

struct KeyValueTable {
  std::string caption;
  std::vector<std::pair<std::string, Value>> rows;
};

/// Numbers under named columns, each row led by a label (a coefficient's name, a test's). NaN is
/// shown as "—" and ±inf as "±∞" (JSON null for both).
struct NumericTable {
  std::string caption;
  std::string label_column;  ///< header of the labels' column ("" = no labels)
  std::vector<std::string> columns;
  std::vector<std::string> labels;
  std::vector<std::vector<double>> rows;
  int digits = 6;                  ///< significant digits shown (report.json has them all)
  std::vector<int> column_digits;  ///< per column, overriding `digits` (empty = `digits` for all)
};

/// A PNG file, embedded. A relative `file` is relative to the report's folder (not to the current
/// one); report.json stores it relative to that folder when it lies inside it. A file that is missing or not a PNG is
/// shown as a note, not an error.
struct Figure {
  std::filesystem::path file;
  std::string caption;
};

/// A symmetric matrix in [-1, 1] (correlations) as a table of coloured cells: blue −1, white 0,
/// red +1. NaN cells (an unidentifiable coefficient) are grey.
struct HeatMap {
  std::string caption;
  std::vector<std::string> labels;
  Eigen::MatrixXd values;
};

using Block = std::variant<Paragraph, KeyValueTable, NumericTable, Figure, HeatMap>;

struct Section {
  std::string id;  ///< one of kSectionOrder, or any other id (shown after them)
  std::string title;
  std::vector<Block> blocks;

  Section& paragraph(std::string text);
  Section& note(std::string text);
  Section& callout(std::string text);
  Section& table(KeyValueTable t);
  Section& table(NumericTable t);
  Section& figure(std::filesystem::path file, std::string caption);
  Section& heat_map(HeatMap h);
};

struct Document {
  std::string title;
  std::string subtitle;
  /// The key results, shown as a row of boxes under the title (termination, f, wall time, …).
  std::vector<std::pair<std::string, Value>> summary;
  std::deque<Section> sections;  ///< a deque: the Section& that section() returns stays valid

  /// The section `id`, appended (titled `title`, or the id's default title) on first use.
  Section& section(const std::string& id, const std::string& title = {});
  /// Sections sorted by kSectionOrder (others after, in the order added).
  std::vector<const Section*> ordered() const;
};

/// Renders the document as one self-contained HTML page. Figures are read from disk and embedded;
/// their relative paths are resolved against `dir`.
std::string to_html(const Document& doc, const std::filesystem::path& dir);
/// report.json's text: the same content, every number as a JSON number (figures by file name).
std::string to_json(const Document& doc, const std::filesystem::path& dir);
/// Reads report.json back (so that a later pipeline can add its sections and write the report
/// again). Throws InputError naming the file for a document it cannot read.
Document read_json(const std::filesystem::path& file);
/// Writes DIR/report.html and DIR/report.json atomically.
void write(const Document& doc, const std::filesystem::path& dir);
/// DIR/report.json read back, `add` applied, and both files written again: how a pipeline that runs
/// after the identification (the demo's timing, the campaign's tables) adds its sections. A missing
/// report.json starts an empty document titled `title`.
template <class F>
void append(const std::filesystem::path& dir, F&& add, const std::string& title = "tricot report") {
  Document d;
  if (std::filesystem::exists(dir / "report.json")) d = read_json(dir / "report.json");
  else d.title = title;
  add(d);
  write(d, dir);
}

/// The kEq9 section from the "eq9" object of an identification's result.json (docs/design.md: per force
/// "whole", "practical", "points_whole", "points_practical", and the "practical" strain domain).
/// Returns false, adding nothing, when the file has no "eq9" or cannot be read.
bool add_eq9(Document& doc, const std::filesystem::path& result_json);

// Building blocks, public for their tests.
/// HTML text: & < > " ' escaped.
std::string escape_html(std::string_view text);
/// Width and height of a PNG from its IHDR chunk; nullopt when `bytes` is not a PNG.
std::optional<std::pair<std::uint32_t, std::uint32_t>> png_size(std::string_view bytes);
/// A number as the report shows it: `digits` significant digits, "—" for NaN, "∞"/"−∞" for inf.
std::string format_number(double x, int digits);
/// The cell colour of a correlation `c` (CSS "#rrggbb"): blue −1, white 0, red +1, grey NaN.
std::string heat_colour(double c);

}  // namespace tricot::project::report
