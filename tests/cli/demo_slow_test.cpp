// tricot demo --table1 end to end (about a minute): the paper's Table 1 reproduced, noise-free.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;

// Issue 4's acceptance for the both-data run: data generated on a finer mesh leave a discretisation
// bias, C03 (the weakest coefficient) the largest.
constexpr double kStrongCoefficients = 1e-3;  // C10, C20, C21 within 0.1 %
constexpr double kC03 = 1e-2;                 // C03 within 1 %

TEST(Demo, ReproducesTableOneFromNoiseFreeData) {
  const fs::path dir = test::scratch_dir("demo");
  const auto r = test::run_tricot("demo --table1 -q -o " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Table 1"), std::string::npos);
  for (const char* f : {"table1.md", "table1.csv", "epsilon.csv", "plots/epsilon.png", "both/result.json",
                        "edge/result.json", "field/result.json", "both/plots/history.png", "experiment/truth.json"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;

  // table1.csv: data,coefficient,target,identified,relative_error,...,termination
  std::istringstream in(io::read_text(dir / "out" / "table1.csv"));
  std::string line;
  std::getline(in, line);
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) c.push_back(cell);
    ASSERT_EQ(c.size(), 13u) << line;
    EXPECT_NE(c[12], "max_iterations") << line;
    ++rows;
    if (c[0] != "both") continue;
    const double e = std::abs(std::stod(c[4]));
    EXPECT_LT(e, c[1] == "C03" ? kC03 : kStrongCoefficients) << line;
  }
  EXPECT_EQ(rows, 12);
}

}  // namespace
}  // namespace tricot
