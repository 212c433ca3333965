// The lab report's document model and its two renderings: a self-contained report.html (inline CSS,
// A4 print stylesheet, figures as base64 data URIs) and report.json (every number as a number).
#include "tricot/project/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <map>

#include "output/json.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/base64.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project::report {

namespace fs = std::filesystem;

namespace {

const std::map<std::string, std::string, std::less<>> kDefaultTitles{
    {kInputs, "Inputs and settings"},
    {kDic, "DIC quality"},
    {kSync, "Synchronisation"},
    {kHistory, "Levenberg–Marquardt history"},
    {kCoefficients, "Identified coefficients"},
    {kCorrelation, "Correlation of the coefficients"},
    {kSurfaces, "Response surfaces"},
    {kEq9, "Eq. 9 errors"},
    {kIdentifiability, "Identifiability"},
    {kFit, "Fit to the measurements"},
    {kTiming, "Wall time"},
};

// The page's style: a sober lab report on screen, A4 with 15 mm margins on paper.
constexpr const char* kCss = R"css(
:root { --ink:#1d2430; --muted:#5b6675; --rule:#c9d0d8; --accent:#1f4e79; --band:#f3f6f9; }
* { box-sizing: border-box; }
html { -webkit-print-color-adjust: exact; print-color-adjust: exact; }
body { margin: 0; background: #e9edf1; color: var(--ink);
       font: 10.5pt/1.45 "DejaVu Sans", "Helvetica Neue", Helvetica, Arial, sans-serif; }
main { max-width: 210mm; margin: 12px auto; background: #fff; padding: 16mm 17mm 14mm;
       box-shadow: 0 1px 4px rgba(0,0,0,.15); }
header.title { border-bottom: 2.5px solid var(--accent); padding-bottom: 8px; margin-bottom: 14px; }
header.title .kicker { font-size: 8.5pt; letter-spacing: .12em; text-transform: uppercase; color: var(--accent);
                       font-weight: bold; }
header.title h1 { font-size: 19pt; margin: 3px 0 2px; font-weight: 600; }
header.title .subtitle { color: var(--muted); font-size: 10pt; }
header.title .stamp { color: var(--muted); font-size: 8.5pt; margin-top: 4px; }
.summary { display: flex; gap: 8px; margin: 0 0 14px; }
.summary div:first-child { flex: 1.8; }
.summary div { flex: 1; border: 1px solid var(--rule); border-top: 3px solid var(--accent); padding: 5px 8px; }
.summary .k { display: block; font-size: 7.5pt; text-transform: uppercase; letter-spacing: .06em; color: var(--muted); }
.summary .v { display: block; font-size: 11pt; font-weight: 600; font-variant-numeric: tabular-nums; }
nav.toc { background: var(--band); border: 1px solid var(--rule); padding: 6px 12px; margin-bottom: 16px;
          font-size: 9.5pt; columns: 2; column-gap: 24px; }
nav.toc a { color: var(--ink); text-decoration: none; display: block; }
nav.toc a span { color: var(--accent); display: inline-block; width: 2em; font-weight: bold; }
section { margin: 0 0 14px; }
h2 { font-size: 12.5pt; color: var(--accent); margin: 18px 0 7px; padding-bottom: 2px;
     border-bottom: 1px solid var(--rule); break-after: avoid; page-break-after: avoid; }
h2 .num { display: inline-block; min-width: 1.6em; }
p { margin: 5px 0 8px; }
p.callout { background: var(--band); border-left: 3px solid var(--accent); padding: 6px 10px; font-size: 9.5pt; }
p.note { color: var(--muted); font-size: 9pt; }
pre.mono, .mono { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 9pt; }
figure, table, .block { break-inside: avoid; page-break-inside: avoid; }
table { border-collapse: collapse; margin: 6px auto 12px; font-size: 9.5pt; font-variant-numeric: tabular-nums; }
table caption { caption-side: top; text-align: left; font-size: 9pt; color: var(--muted); padding-bottom: 3px; }
table caption b { color: var(--ink); }
table.data { border-top: 1.5px solid var(--ink); border-bottom: 1.5px solid var(--ink); width: 100%; }
table.data th { border-bottom: 1px solid var(--ink); font-weight: 600; padding: 3px 8px; text-align: right;
                vertical-align: bottom; }
table.data td { padding: 2px 10px; text-align: right; border-bottom: 1px solid #eef1f4; white-space: nowrap; }
table.data th.label, table.data td.label { text-align: left; }
table.data.wide { font-size: 8.5pt; }
table.data.wide th, table.data.wide td { padding-left: 4px; padding-right: 4px; }
table.kv { border-top: 1.5px solid var(--ink); border-bottom: 1.5px solid var(--ink); width: 100%; }
table.kv td { padding: 2px 8px; border-bottom: 1px solid #eef1f4; vertical-align: top; }
table.kv td.key { color: var(--muted); width: 34%; }
table.kv td.num { font-variant-numeric: tabular-nums; }
figure { margin: 8px 0 14px; text-align: center; }
figure img { max-width: 100%; max-height: 125mm; height: auto; border: 1px solid var(--rule); }
figcaption { font-size: 9pt; color: var(--muted); margin-top: 4px; text-align: left; }
figcaption b, table caption b { color: var(--ink); }
.missing { border: 1px dashed var(--rule); color: var(--muted); padding: 10px; font-size: 9pt; }
table.heat { margin: 6px auto 4px; border: none; }
table.heat th { font-weight: 600; padding: 3px 8px; font-size: 9pt; }
table.heat td { width: 64px; height: 30px; text-align: center; font-size: 9pt; border: 1px solid #fff; }
.legend { display: flex; align-items: center; justify-content: center; gap: 6px; font-size: 8.5pt; color: var(--muted);
          margin-bottom: 12px; }
.legend .bar { width: 180px; height: 10px; border: 1px solid var(--rule);
               background: linear-gradient(to right, #2166ac, #ffffff, #b2182b); }
footer { margin-top: 18px; padding-top: 6px; border-top: 1px solid var(--rule); font-size: 8pt; color: var(--muted); }
@page { size: A4; margin: 14mm 15mm 16mm; }
@media print {
  body { background: #fff; font-size: 10pt; }
  main { max-width: none; margin: 0; padding: 0; box-shadow: none; }
  nav.toc a { color: var(--ink); }
  a { color: inherit; text-decoration: none; }
}
)css";

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

json number_json(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

std::string value_text(const Value& v) {
  if (!v.is_number()) return std::get<std::string>(v.v);
  std::string s = format_number(std::get<double>(v.v), v.digits);
  if (!v.unit.empty()) s += " " + v.unit;
  return s;
}

fs::path resolve(const fs::path& file, const fs::path& dir) { return file.is_absolute() ? file : dir / file; }

// The figure's path as report.json stores it: relative to the report's folder when inside it.
std::string stored_path(const fs::path& file, const fs::path& dir) {
  const fs::path abs = fs::absolute(resolve(file, dir)).lexically_normal();
  const fs::path rel = abs.lexically_relative(fs::absolute(dir).lexically_normal());
  if (!rel.empty() && *rel.begin() != "..") return rel.generic_string();
  return abs.generic_string();
}

std::string read_bytes(const fs::path& p) {
  try {
    return io::read_text(p);
  } catch (const InputError&) {
    return {};
  }
}

std::string caption_html(const std::string& kind, int number, const std::string& caption) {
  return fmt::format("<b>{} {}.</b> {}", kind, number, escape_html(caption));
}

struct Counters {
  int table = 0, figure = 0;
};

void render(std::string& h, const Block& b, const fs::path& dir, Counters& n) {
  if (const auto* p = std::get_if<Paragraph>(&b)) {
    const char* cls = p->style == Paragraph::Style::note      ? " class=\"note\""
                      : p->style == Paragraph::Style::callout ? " class=\"callout\""
                                                              : "";
    h += fmt::format("<p{}>{}</p>\n", cls, escape_html(p->text));
  } else if (const auto* t = std::get_if<KeyValueTable>(&b)) {
    h += "<table class=\"kv\">";
    if (!t->caption.empty()) h += "<caption>" + caption_html("Table", ++n.table, t->caption) + "</caption>";
    for (const auto& [k, v] : t->rows)
      h += fmt::format("<tr><td class=\"key\">{}</td><td{}>{}</td></tr>", escape_html(k),
                       v.is_number() ? " class=\"num\"" : "", escape_html(value_text(v)));
    h += "</table>\n";
  } else if (const auto* t = std::get_if<NumericTable>(&b)) {
    const bool labels = !t->label_column.empty() || !t->labels.empty();
    h += t->columns.size() > 7 ? "<table class=\"data wide\">" : "<table class=\"data\">";
    if (!t->caption.empty()) h += "<caption>" + caption_html("Table", ++n.table, t->caption) + "</caption>";
    h += "<thead><tr>";
    if (labels) h += "<th class=\"label\">" + escape_html(t->label_column) + "</th>";
    for (const auto& c : t->columns) h += "<th>" + escape_html(c) + "</th>";
    h += "</tr></thead><tbody>";
    for (std::size_t r = 0; r < t->rows.size(); ++r) {
      h += "<tr>";
      if (labels) h += "<td class=\"label\">" + escape_html(r < t->labels.size() ? t->labels[r] : "") + "</td>";
      for (std::size_t c = 0; c < t->rows[r].size(); ++c)
        h += "<td>" +
             escape_html(format_number(t->rows[r][c], c < t->column_digits.size() ? t->column_digits[c] : t->digits)) +
             "</td>";
      h += "</tr>";
    }
    h += "</tbody></table>\n";
  } else if (const auto* f = std::get_if<Figure>(&b)) {
    const fs::path path = resolve(f->file, dir);
    const std::string bytes = read_bytes(path);
    const auto size = png_size(bytes);
    ++n.figure;
    if (!size) {
      h += fmt::format(
          "<figure><div class=\"missing\">Figure not available: {} was not drawn (plots turned off, or gnuplot "
          "missing).</div>"
          "<figcaption>{}</figcaption></figure>\n",
          escape_html(stored_path(f->file, dir)), caption_html("Figure", n.figure, f->caption));
      return;
    }
    h += fmt::format(
        "<figure><img src=\"data:image/png;base64,{}\" width=\"{}\" height=\"{}\" alt=\"{}\">"
        "<figcaption>{}</figcaption></figure>\n",
        io::base64(bytes), size->first, size->second, escape_html(f->caption),
        caption_html("Figure", n.figure, f->caption));
  } else if (const auto* m = std::get_if<HeatMap>(&b)) {
    h += "<div class=\"block\"><table class=\"heat\">";
    if (!m->caption.empty()) h += "<caption>" + caption_html("Table", ++n.table, m->caption) + "</caption>";
    h += "<tr><th></th>";
    for (const auto& l : m->labels) h += "<th>" + escape_html(l) + "</th>";
    h += "</tr>";
    for (Eigen::Index i = 0; i < m->values.rows(); ++i) {
      h += "<tr><th>" + escape_html(std::size_t(i) < m->labels.size() ? m->labels[std::size_t(i)] : "") + "</th>";
      for (Eigen::Index k = 0; k < m->values.cols(); ++k) {
        const double c = m->values(i, k);
        const bool dark = std::isfinite(c) && std::abs(c) > 0.55;
        h += fmt::format("<td style=\"background:{};color:{}\">{}</td>", heat_colour(c), dark ? "#ffffff" : "#1d2430",
                         escape_html(std::isfinite(c) ? fmt::format("{:+.2f}", c) : format_number(c, 2)));
      }
      h += "</tr>";
    }
    h += "</table><div class=\"legend\">−1<span class=\"bar\"></span>+1</div></div>\n";
  }
}

double json_number(const json& j) { return j.is_null() ? std::nan("") : j.get<double>(); }

json rows_json(const std::vector<std::pair<std::string, Value>>& rows) {
  json out = json::array();
  for (const auto& [k, v] : rows) {
    json r = {{"key", k}};
    if (v.is_number()) {
      r["value"] = number_json(std::get<double>(v.v));
      r["digits"] = v.digits;
      if (!v.unit.empty()) r["unit"] = v.unit;
    } else {
      r["value"] = std::get<std::string>(v.v);
    }
    out.push_back(r);
  }
  return out;
}

std::vector<std::pair<std::string, Value>> rows_from_json(const json& rows) {
  std::vector<std::pair<std::string, Value>> out;
  for (const auto& r : rows) {
    const auto& v = r.at("value");
    if (v.is_string()) out.emplace_back(r.at("key").get<std::string>(), Value(v.get<std::string>()));
    else
      out.emplace_back(r.at("key").get<std::string>(),
                       Value(json_number(v), r.value("digits", 6), r.value("unit", "")));
  }
  return out;
}

json block_json(const Block& b, const fs::path& dir) {
  json j;
  if (const auto* p = std::get_if<Paragraph>(&b)) {
    j = {{"type", p->style == Paragraph::Style::note      ? "note"
                  : p->style == Paragraph::Style::callout ? "callout"
                                                          : "paragraph"},
         {"text", p->text}};
  } else if (const auto* t = std::get_if<KeyValueTable>(&b)) {
    j = {{"type", "key_value"}, {"caption", t->caption}, {"rows", rows_json(t->rows)}};
  } else if (const auto* t = std::get_if<NumericTable>(&b)) {
    json rows = json::array();
    for (const auto& row : t->rows) {
      json r = json::array();
      for (double x : row) r.push_back(number_json(x));
      rows.push_back(r);
    }
    j = {{"type", "table"},       {"caption", t->caption}, {"label_column", t->label_column},
         {"columns", t->columns}, {"labels", t->labels},   {"rows", rows},
         {"digits", t->digits}};
    if (!t->column_digits.empty()) j["column_digits"] = t->column_digits;
  } else if (const auto* f = std::get_if<Figure>(&b)) {
    const auto size = png_size(read_bytes(resolve(f->file, dir)));
    j = {{"type", "figure"}, {"file", stored_path(f->file, dir)}, {"caption", f->caption}};
    if (size) {
      j["width"] = size->first;
      j["height"] = size->second;
    } else {
      j["missing"] = true;
    }
  } else if (const auto* m = std::get_if<HeatMap>(&b)) {
    json rows = json::array();
    for (Eigen::Index i = 0; i < m->values.rows(); ++i) {
      json r = json::array();
      for (Eigen::Index k = 0; k < m->values.cols(); ++k) r.push_back(number_json(m->values(i, k)));
      rows.push_back(r);
    }
    j = {{"type", "heat_map"}, {"caption", m->caption}, {"labels", m->labels}, {"values", rows}};
  }
  return j;
}

Block block_from_json(const json& j) {
  const std::string type = j.at("type").get<std::string>();
  if (type == "paragraph" || type == "note" || type == "callout")
    return Paragraph{j.at("text").get<std::string>(), type == "note"      ? Paragraph::Style::note
                                                      : type == "callout" ? Paragraph::Style::callout
                                                                          : Paragraph::Style::body};
  if (type == "key_value") {
    return KeyValueTable{j.value("caption", ""), rows_from_json(j.at("rows"))};
  }
  if (type == "table") {
    NumericTable t;
    t.caption = j.value("caption", "");
    t.label_column = j.value("label_column", "");
    t.columns = j.at("columns").get<std::vector<std::string>>();
    t.labels = j.at("labels").get<std::vector<std::string>>();
    t.digits = j.value("digits", 6);
    if (j.contains("column_digits")) t.column_digits = j.at("column_digits").get<std::vector<int>>();
    for (const auto& r : j.at("rows")) {
      std::vector<double> row;
      for (const auto& x : r) row.push_back(json_number(x));
      t.rows.push_back(std::move(row));
    }
    return t;
  }
  if (type == "figure") return Figure{j.at("file").get<std::string>(), j.value("caption", "")};
  if (type == "heat_map") {
    HeatMap m{j.value("caption", ""), j.at("labels").get<std::vector<std::string>>(), {}};
    const auto& rows = j.at("values");
    m.values.resize(Eigen::Index(rows.size()), rows.empty() ? 0 : Eigen::Index(rows[0].size()));
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t k = 0; k < rows[i].size(); ++k)
        m.values(Eigen::Index(i), Eigen::Index(k)) = json_number(rows[i][k]);
    return m;
  }
  throw std::out_of_range("unknown block type " + type);
}

}  // namespace

Section& Section::paragraph(std::string text) {
  blocks.emplace_back(Paragraph{std::move(text), Paragraph::Style::body});
  return *this;
}
Section& Section::note(std::string text) {
  blocks.emplace_back(Paragraph{std::move(text), Paragraph::Style::note});
  return *this;
}
Section& Section::callout(std::string text) {
  blocks.emplace_back(Paragraph{std::move(text), Paragraph::Style::callout});
  return *this;
}
Section& Section::table(KeyValueTable t) {
  blocks.emplace_back(std::move(t));
  return *this;
}
Section& Section::table(NumericTable t) {
  blocks.emplace_back(std::move(t));
  return *this;
}
Section& Section::figure(fs::path file, std::string caption) {
  blocks.emplace_back(Figure{std::move(file), std::move(caption)});
  return *this;
}
Section& Section::heat_map(HeatMap h) {
  blocks.emplace_back(std::move(h));
  return *this;
}

Section& Document::section(const std::string& id, const std::string& title) {
  for (auto& s : sections)
    if (s.id == id) return s;
  const auto d = kDefaultTitles.find(id);
  sections.push_back(Section{id, !title.empty() ? title : d != kDefaultTitles.end() ? d->second : id, {}});
  return sections.back();
}

std::vector<const Section*> Document::ordered() const {
  std::vector<const Section*> out;
  for (const auto& s : sections) out.push_back(&s);
  const auto rank = [](const Section* s) {
    return std::size_t(std::find(kSectionOrder.begin(), kSectionOrder.end(), s->id) - kSectionOrder.begin());
  };
  std::stable_sort(out.begin(), out.end(), [&](const Section* a, const Section* b) { return rank(a) < rank(b); });
  return out;
}

std::string to_html(const Document& doc, const fs::path& dir) {
  const auto sections = doc.ordered();
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += "<title>" + escape_html(doc.title) + "</title>\n<style>" + std::string(kCss) +
       "</style>\n</head>\n<body>\n<main>\n";
  h += "<header class=\"title\"><div class=\"kicker\">tricot · identification report</div>";
  h += "<h1>" + escape_html(doc.title) + "</h1>";
  if (!doc.subtitle.empty()) h += "<div class=\"subtitle\">" + escape_html(doc.subtitle) + "</div>";
  h += "<div class=\"stamp\">Generated " + escape_html(utc_now()) +
       " · every number of this page is in report.json</div></header>\n";
  if (!doc.summary.empty()) {
    h += "<div class=\"summary\">";
    for (const auto& [k, v] : doc.summary)
      h += fmt::format("<div><span class=\"k\">{}</span><span class=\"v\">{}</span></div>", escape_html(k),
                       escape_html(value_text(v)));
    h += "</div>\n";
  }
  if (sections.size() > 1) {
    h += "<nav class=\"toc\">";
    for (std::size_t i = 0; i < sections.size(); ++i)
      h += fmt::format("<a href=\"#{}\"><span>{}</span>{}</a>", escape_html(sections[i]->id), i + 1,
                       escape_html(sections[i]->title));
    h += "</nav>\n";
  }
  Counters n;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const Section& s = *sections[i];
    h += fmt::format("<section id=\"{}\">\n<h2><span class=\"num\">{}</span>{}</h2>\n", escape_html(s.id), i + 1,
                     escape_html(s.title));
    for (const auto& b : s.blocks) render(h, b, dir, n);
    h += "</section>\n";
  }
  h += "<footer>tricot — identification of knitted-fabric laws by FE model updating from DIC fields "
       "(after Gaied, Drapier &amp; Lun 2007). Self-contained page: figures are embedded.</footer>\n";
  h += "</main>\n</body>\n</html>\n";
  return h;
}

std::string to_json(const Document& doc, const fs::path& dir) {
  json j;
  j["title"] = doc.title;
  j["subtitle"] = doc.subtitle;
  j["generated"] = utc_now();
  j["summary"] = rows_json(doc.summary);
  json sections = json::array();
  for (const Section* s : doc.ordered()) {
    json blocks = json::array();
    for (const auto& b : s->blocks) blocks.push_back(block_json(b, dir));
    sections.push_back({{"id", s->id}, {"title", s->title}, {"blocks", blocks}});
  }
  j["sections"] = sections;
  return j.dump(2) + "\n";
}

Document read_json(const fs::path& file) {
  Document d;
  try {
    const json j = json::parse(io::read_text(file));
    d.title = j.value("title", "");
    d.subtitle = j.value("subtitle", "");
    if (j.contains("summary")) d.summary = rows_from_json(j.at("summary"));
    for (const auto& s : j.at("sections")) {
      Section& sec = d.section(s.at("id").get<std::string>(), s.value("title", ""));
      for (const auto& b : s.at("blocks")) sec.blocks.push_back(block_from_json(b));
    }
  } catch (const json::exception& e) {
    throw InputError({file.string(), 0, {}}, "not a tricot report.json", json_problem(e));
  } catch (const std::out_of_range& e) {
    throw InputError({file.string(), 0, "type"}, "not a tricot report.json", e.what());
  }
  return d;
}

void write(const Document& doc, const fs::path& dir) {
  io::write_atomic(dir / "report.json", to_json(doc, dir));
  io::write_atomic(dir / "report.html", to_html(doc, dir));
}

std::string escape_html(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::optional<std::pair<std::uint32_t, std::uint32_t>> png_size(std::string_view b) {
  // Signature (8 bytes), then the IHDR chunk: length (4), "IHDR" (4), width (4), height (4), big-endian.
  static constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
  if (b.size() < 24 || b.substr(0, 8) != kSignature || b.substr(12, 4) != "IHDR") return std::nullopt;
  const auto be32 = [&](std::size_t o) {
    return std::uint32_t(std::uint8_t(b[o])) << 24 | std::uint32_t(std::uint8_t(b[o + 1])) << 16 |
           std::uint32_t(std::uint8_t(b[o + 2])) << 8 | std::uint32_t(std::uint8_t(b[o + 3]));
  };
  const std::uint32_t w = be32(16), h = be32(20);
  if (w == 0 || h == 0) return std::nullopt;
  return std::pair{w, h};
}

std::string format_number(double x, int digits) {
  if (std::isnan(x)) return "—";
  if (std::isinf(x)) return x > 0 ? "∞" : "−∞";
  return fmt::format("{:.{}g}", x, std::max(1, digits));
}

std::string heat_colour(double c) {
  if (!std::isfinite(c)) return "#bfc5cc";
  const double t = std::clamp(std::abs(c), 0.0, 1.0);
  // White to the end colour, linearly in sRGB: #2166ac (−1) and #b2182b (+1), ColorBrewer RdBu's ends.
  const int end[3] = {c < 0 ? 0x21 : 0xb2, c < 0 ? 0x66 : 0x18, c < 0 ? 0xac : 0x2b};
  int rgb[3];
  for (int k = 0; k < 3; ++k) rgb[k] = int(std::lround(255 + t * (end[k] - 255)));
  return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}

}  // namespace tricot::project::report
