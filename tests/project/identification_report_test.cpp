// The report of `tricot identify` (src/project/output/identification_report.cpp): a small synth + identify,
// then report.json checked against result.json, number for number.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/report.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// report.json and result.json both write doubles in nlohmann's shortest round-trip form, so their
// numbers compare exactly (EXPECT_EQ). The 95 % interval is J ± 1.959963984540054·s.e. (normal quantile): a few ulps of
// J.
constexpr double kIntervalRoundOff = 1e-15;

const json& section(const json& report, const std::string& id) {
  for (const auto& s : report["sections"])
    if (s["id"] == id) return s;
  throw std::runtime_error("no section " + id);
}

// The first block of `type` in a section.
const json& block(const json& s, const std::string& type) {
  for (const auto& b : s["blocks"])
    if (b["type"] == type) return b;
  throw std::runtime_error("no " + type + " block in " + s["id"].get<std::string>());
}

TEST(IdentificationReport, HoldsTheNumbersOfResultJsonAndTheSectionsInOrder) {
  const fs::path dir = test::scratch_dir("identification_report_" + std::to_string(::getpid()));
  test::write_file(dir / "experiment.toml", test::small_experiment());
  auto r = test::run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  test::write_file(dir / "project.toml", test::small_project("exp"));
  // A run with plots, then one without into the same folder: the second report must not show the
  // first run's plots.
  const std::string identify = "identify " + (dir / "project.toml").string() + " -o " + (dir / "out").string() + " -q";
  r = test::run_tricot(identify);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_NE(io::read_text(dir / "out" / "report.html").find("<img"), std::string::npos);
  r = test::run_tricot(identify + " --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const json result = json::parse(io::read_text(dir / "out" / "result.json"));
  const json report = json::parse(io::read_text(dir / "out" / "report.json"));
  std::vector<std::string> ids;
  for (const auto& s : report["sections"]) ids.push_back(s["id"]);
  // eq. 9 (docs/theory.md §9) is reported for every identification whose tests give experimental points (here
  // the uniaxial test's steps), so its section stands between the correlation and the identifiability.
  EXPECT_EQ(ids, (std::vector<std::string>{"inputs", "history", "coefficients", "correlation", "eq9", "identifiability",
                                           "timing"}));

  // Coefficients: start, identified, s.e., rel. s.e. %, 95 % low, 95 % high, truth, rel. error %, error / s.e.
  const json& table = block(section(report, "coefficients"), "table");
  const std::vector<std::string> names = result["names"];
  ASSERT_EQ(table["labels"].get<std::vector<std::string>>(), names);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const json& row = table["rows"][k];
    const double J = result["parameters"][names[k]], se = result["std_error"][names[k]];
    EXPECT_EQ(row[0].get<double>(), result["start"][names[k]].get<double>()) << names[k];
    EXPECT_EQ(row[1].get<double>(), J) << names[k];
    EXPECT_EQ(row[2].get<double>(), se) << names[k];
    EXPECT_NEAR(row[4].get<double>(), J - 1.959963984540054 * se, kIntervalRoundOff * std::abs(J)) << names[k];
    EXPECT_NEAR(row[5].get<double>(), J + 1.959963984540054 * se, kIntervalRoundOff * std::abs(J)) << names[k];
    EXPECT_EQ(row[6].get<double>(), result["truth"][names[k]].get<double>()) << names[k];
  }
  // The heat map is result.json's correlation matrix.
  EXPECT_EQ(block(section(report, "correlation"), "heat_map")["values"], result["correlation"]);
  // The termination table's f and iterations.
  const json& term = block(section(report, "coefficients"), "key_value")["rows"];
  bool f_found = false;
  for (const auto& row : term)
    if (row["key"] == "objective f(J*)") {
      EXPECT_EQ(row["value"].get<double>(), result["objective"].get<double>());
      f_found = true;
    } else if (row["key"] == "LM iterations") {
      EXPECT_EQ(row["value"].get<double>(), result["iterations"].get<double>());
    }
  EXPECT_TRUE(f_found);
  // Without plots the history figure is a note, and the page references no other file.
  EXPECT_NE(block(section(report, "history"), "note")["text"].get<std::string>().find("No plot"), std::string::npos);
  const std::string html = io::read_text(dir / "out" / "report.html");
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);
}

TEST(AddEq9, TabulatesResultJsonsEq9PerForceWithThePracticalDomain) {
  const fs::path dir = test::scratch_dir("report_eq9_" + std::to_string(::getpid()));
  // The shape campaign's identify writes (docs/design.md); wale has no practical point (null).
  test::write_file(dir / "result.json", R"({"eq9": {
    "course": {"whole": 0.244, "practical": 0.055, "points_whole": 60, "points_practical": 7},
    "wale": {"whole": 0.774, "practical": null, "points_whole": 60, "points_practical": 0},
    "practical": {"course": [0.0, 0.3], "wale": [-0.05, 0.2]}}})");
  report::Document d;
  ASSERT_TRUE(report::add_eq9(d, dir / "result.json"));
  ASSERT_EQ(d.sections.size(), 1u);
  ASSERT_EQ(d.sections[0].id, report::kEq9);
  const auto& t = std::get<report::NumericTable>(d.sections[0].blocks[0]);
  EXPECT_EQ(t.labels, (std::vector<std::string>{"course", "wale"}));
  EXPECT_EQ(t.rows[0], (std::vector<double>{0.244, 0.055, 60, 7}));
  EXPECT_EQ(t.rows[1][0], 0.774);
  EXPECT_TRUE(std::isnan(t.rows[1][1]));
  const auto& p = std::get<report::NumericTable>(d.sections[0].blocks[1]);
  EXPECT_EQ(p.labels, (std::vector<std::string>{"course", "wale"}));
  EXPECT_EQ(p.rows[1], (std::vector<double>{-0.05, 0.2}));
  // No eq9 (a Mooney–Rivlin run), or no file: nothing added.
  test::write_file(dir / "plain.json", R"({"parameters": {"C10": 0.1}})");
  report::Document none;
  EXPECT_FALSE(report::add_eq9(none, dir / "plain.json"));
  EXPECT_FALSE(report::add_eq9(none, dir / "absent.json"));
  EXPECT_TRUE(none.sections.empty());
}

}  // namespace
}  // namespace tricot::project
