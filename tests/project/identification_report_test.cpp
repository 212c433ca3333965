// The report of `tricot identify` (src/project/identification_report.cpp): a small synth + identify,
// then report.json checked against result.json, number for number.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// report.json and result.json both write doubles in nlohmann's shortest round-trip form, so their
// numbers compare exactly (EXPECT_EQ). The 95 % interval is J ± 1.959963984540054·s.e. (normal quantile): a few ulps of J.
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
  r = test::run_tricot("identify " + (dir / "project.toml").string() + " -o " + (dir / "out").string() + " -q --no-plots");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const json result = json::parse(io::read_text(dir / "out" / "result.json"));
  const json report = json::parse(io::read_text(dir / "out" / "report.json"));
  std::vector<std::string> ids;
  for (const auto& s : report["sections"]) ids.push_back(s["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"inputs", "history", "coefficients", "correlation", "identifiability", "timing"}));

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
  // Without plots the figures are notes, and the page still references no other file.
  EXPECT_TRUE(block(section(report, "history"), "figure")["missing"].get<bool>());
  const std::string html = io::read_text(dir / "out" / "report.html");
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);
}

}  // namespace
}  // namespace tricot::project
