// The lab report's writer (src/project/output/report.cpp): escaping, PNG sizes, heat colours,
// section order, and report.json holding every number the page shows.
#include "tricot/project/report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/base64.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project::report {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The smallest valid PNG: one grey pixel (signature, IHDR 1 × 1 8-bit grey, IDAT, IEND).
const std::string kOnePixelPng(
    "\x89PNG\r\n\x1a\n"
    "\x00\x00\x00\x0dIHDR\x00\x00\x00\x01\x00\x00\x00\x01\x08\x00\x00\x00\x00\x3a\x7e\x9b\x55"
    "\x00\x00\x00\x0aIDAT\x78\x9c\x63\x60\x00\x00\x00\x02\x00\x01\xe5\x27\xde\xfc"
    "\x00\x00\x00\x00IEND\xae\x42\x60\x82",
    67);

TEST(EscapeHtml, EscapesTheFiveSpecialCharactersAndKeepsTheRest) {
  EXPECT_EQ(escape_html(R"(<a href="x">Tom & Jerry's</a>)"),
            "&lt;a href=&quot;x&quot;&gt;Tom &amp; Jerry&#39;s&lt;/a&gt;");
  EXPECT_EQ(escape_html("σ̂² = 2f/(N − n)"), "σ̂² = 2f/(N − n)");
}

TEST(PngSize, ReadsWidthAndHeightFromIhdrAndRejectsOtherBytes) {
  const auto s = png_size(kOnePixelPng);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->first, 1u);
  EXPECT_EQ(s->second, 1u);
  std::string wide = kOnePixelPng;
  wide[16 + 2] = '\x01';  // width 0x00000101 = 257
  wide[20 + 3] = '\x07';  // height 7
  EXPECT_EQ(png_size(wide)->first, 257u);
  EXPECT_EQ(png_size(wide)->second, 7u);
  EXPECT_FALSE(png_size("GIF89a........................"));
  EXPECT_FALSE(png_size(kOnePixelPng.substr(0, 20)));
}

TEST(FormatNumber, GivesSignificantDigitsAndMarksNanAndInfinity) {
  EXPECT_EQ(format_number(0.0123456789, 3), "0.0123");
  EXPECT_EQ(format_number(-25000, 2), "-2.5e+04");
  EXPECT_EQ(format_number(std::nan(""), 3), "—");
  EXPECT_EQ(format_number(INFINITY, 3), "∞");
  EXPECT_EQ(format_number(-INFINITY, 3), "−∞");
}

TEST(HeatColour, GoesFromBlueThroughWhiteToRed) {
  EXPECT_EQ(heat_colour(-1), "#2166ac");
  EXPECT_EQ(heat_colour(0), "#ffffff");
  EXPECT_EQ(heat_colour(1), "#b2182b");
  EXPECT_EQ(heat_colour(0.5), "#d98c95");  // halfway: (255 + 0xb2)/2 = 216.5 → 217 = 0xd9, …
  EXPECT_EQ(heat_colour(std::nan("")), "#bfc5cc");
}

TEST(Document, ShowsSectionsInTheCanonicalOrderWhateverTheOrderAdded) {
  Document d;
  d.section(kTiming);
  d.section("appendix", "Appendix");
  d.section(kInputs);
  d.section(kCorrelation).paragraph("a");
  d.section(kCorrelation).paragraph("b");  // the same section again
  const auto s = d.ordered();
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0]->id, kInputs);
  EXPECT_EQ(s[1]->id, kCorrelation);
  EXPECT_EQ(s[1]->blocks.size(), 2u);
  EXPECT_EQ(s[2]->id, kTiming);
  EXPECT_EQ(s[3]->title, "Appendix");
}

// A document with one block of each kind, and its figure on disk.
Document sample(const fs::path& dir) {
  io::write_atomic(dir / "plots" / "one.png", kOnePixelPng);
  Document d;
  d.title = "Law <A> & B";
  d.summary = {{"f", Value(2.5e-13, 2)}, {"wall time", Value(1.5, 3, "s")}};
  d.section(kInputs).paragraph("x < y").table(
      KeyValueTable{"settings", {{"epsilon", Value(1.25e-12, 3)}, {"law", "mr"}}});
  NumericTable t{"coefficients", "name", {"value", "s.e."}, {"C10"}, {{0.123456789, std::nan("")}}, 4,
                 {3, 2}};  // 3 digits in the first column
  d.section(kCoefficients).table(t);
  Eigen::MatrixXd c(2, 2);
  c << 1, -0.875, -0.875, 1;
  d.section(kCorrelation).heat_map(HeatMap{"corr", {"C10", "C20"}, c});
  d.section(kHistory).figure(dir / "plots" / "one.png", "one pixel").figure("plots/absent.png", "never drawn");
  return d;
}

TEST(Html, IsSelfContainedWithTheFigureEmbeddedAndTextEscaped) {
  const fs::path dir = test::scratch_dir("report_html");
  const std::string h = to_html(sample(dir), dir);
  EXPECT_NE(h.find("<title>Law &lt;A&gt; &amp; B</title>"), std::string::npos);
  EXPECT_NE(h.find("<p>x &lt; y</p>"), std::string::npos);
  EXPECT_NE(h.find("<span class=\"v\">1.5 s</span>"), std::string::npos);
  EXPECT_NE(h.find("src=\"data:image/png;base64," + io::base64(kOnePixelPng) + "\" width=\"1\" height=\"1\""),
            std::string::npos);
  EXPECT_NE(h.find("Figure not available: plots/absent.png"), std::string::npos);
  EXPECT_NE(h.find("@page { size: A4"), std::string::npos);
  EXPECT_NE(h.find("background:" + heat_colour(-0.875)), std::string::npos);
  EXPECT_NE(h.find("<td>0.123</td><td>—</td>"), std::string::npos);
  // Nothing fetched from elsewhere: no http(s) URL, no link or script element.
  EXPECT_EQ(h.find("http"), std::string::npos);
  EXPECT_EQ(h.find("<link"), std::string::npos);
  EXPECT_EQ(h.find("<script"), std::string::npos);
}

TEST(Json, HoldsEveryNumberOfThePageAsANumber) {
  const fs::path dir = test::scratch_dir("report_json");
  const json j = json::parse(to_json(sample(dir), dir));
  ASSERT_EQ(j["sections"].size(), 4u);
  EXPECT_EQ(j["summary"][0]["value"].get<double>(), 2.5e-13);
  EXPECT_EQ(j["summary"][1]["unit"], "s");
  const json& inputs = j["sections"][0]["blocks"];
  EXPECT_EQ(inputs[0]["text"], "x < y");
  EXPECT_EQ(inputs[1]["rows"][0]["value"].get<double>(), 1.25e-12);
  EXPECT_EQ(inputs[1]["rows"][1]["value"], "mr");
  const json& history = j["sections"][1]["blocks"];
  EXPECT_EQ(history[0]["file"], "plots/one.png");  // relative to the report
  EXPECT_EQ(history[0]["width"], 1);
  EXPECT_TRUE(history[1]["missing"].get<bool>());
  const json& table = j["sections"][2]["blocks"][0];
  EXPECT_EQ(table["rows"][0][0].get<double>(), 0.123456789);  // full precision, not the 3 digits shown
  EXPECT_TRUE(table["rows"][0][1].is_null());                 // NaN
  EXPECT_EQ(j["sections"][3]["blocks"][0]["values"][0][1].get<double>(), -0.875);
}

TEST(Json, ReadsBackToTheSamePageSoThatLaterPipelinesCanAddSections) {
  const fs::path dir = test::scratch_dir("report_round_trip");
  const Document d = sample(dir);
  write(d, dir);
  append(dir, [](Document& doc) {
    doc.section(kTiming).table(NumericTable{"stages", "stage", {"s"}, {"DIC"}, {{12.5}}, 3, {}});
  });
  const Document back = read_json(dir / "report.json");
  EXPECT_EQ(to_html(back, dir).find("12.5") != std::string::npos, true);
  // The first four sections are unchanged: the same page, but for the added section.
  Document without = back;
  without.sections.erase(std::remove_if(without.sections.begin(), without.sections.end(),
                                        [](const Section& s) { return s.id == kTiming; }),
                         without.sections.end());
  EXPECT_EQ(back.summary.size(), 2u);
  EXPECT_EQ(to_json(without, dir).substr(to_json(without, dir).find("\"sections\"")),
            to_json(d, dir).substr(to_json(d, dir).find("\"sections\"")));
  EXPECT_TRUE(fs::exists(dir / "report.html"));
}

TEST(Json, ReadingSomethingElseIsAnInputErrorNamingTheFile) {
  const fs::path dir = test::scratch_dir("report_bad");
  io::write_atomic(dir / "report.json", "{\"sections\": [{\"id\": \"x\", \"blocks\": [{\"type\": \"video\"}]}]}");
  try {
    read_json(dir / "report.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("report.json"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("video"), std::string::npos);
  }
}

}  // namespace
}  // namespace tricot::project::report
