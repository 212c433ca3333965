// An identification on any specimen (issue 28): examples/strip-with-hole, a Gmsh strip with a hole
// pulled from one side, loaded, held and unloaded, through tricot synth and tricot identify.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "testing/cli.hpp"
#include "tricot/io/files.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;

constexpr double kNoiseFree = 1e-6;  // same mesh as the truth, no noise: LM stops at f < 1e-12
// With noise, on a coarser mesh than the truth's (3 mm against 2 mm): measured 2.28 s.e. for μ and
// 0.69 for λ; the mesh's own bias is part of it.
constexpr double kStandardErrors = 3;

std::string text(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

nlohmann::json identify(const fs::path& dir) {
  const auto s =
      run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "experiment").string() + " -q");
  EXPECT_EQ(s.exit_code, 0) << s.err;
  const auto r = run_tricot("identify " + (dir / "project.toml").string() + " -o " + (dir / "out").string() + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(text(dir / "out" / "result.json"));
}

fs::path copy_example(const std::string& name) {
  const fs::path dir = test::scratch_dir(name), from = test::source_dir() / "examples" / "strip-with-hole";
  for (const char* f : {"strip.geo", "experiment.toml", "project.toml"}) fs::copy_file(from / f, dir / f);
  return dir;
}

void edit(const fs::path& file, const std::string& pattern, const std::string& with) {
  const std::string t = std::regex_replace(text(file), std::regex(pattern), with);
  std::ofstream(file) << t;
}

// An example's experiment made noise-free on the project's own mesh (the truth's mesh size `truth`
// becomes the project's `project`), its σ no longer taken from truth.json.
void noise_free_on_the_projects_mesh(const fs::path& dir, const std::string& force_noise,
                                     const std::string& field_noise, const std::string& truth,
                                     const std::string& project) {
  edit(dir / "experiment.toml", force_noise, "noise_edge_force = 0.0");
  edit(dir / "experiment.toml", field_noise, "noise_field = 0.0");
  edit(dir / "experiment.toml", truth, project);
  edit(dir / "project.toml", "sigma_from_truth = true", "sigma_from_truth = false");
}

TEST(StripWithAHole, NoiseFreeDataOnTheTruthsMeshGiveTheTruth) {
  const fs::path dir = copy_example("strip_noise_free");
  noise_free_on_the_projects_mesh(dir, "noise_edge_force = 0.02", "noise_field = 0.005", "size = 2.0", "size = 3.0");
  const nlohmann::json r = identify(dir);
  EXPECT_NEAR(r["parameters"]["mu"].get<double>(), 0.5, kNoiseFree * 0.5);
  EXPECT_NEAR(r["parameters"]["lambda"].get<double>(), 1.0, kNoiseFree * 1.0);
  // The identified law replayed on the project's tests (tricot simulate --law, issue 29): its clamp
  // force is the noise-free data's, step by step (the loads come from forces.csv).
  const auto s =
      run_tricot("simulate " + (dir / "project.toml").string() + " --law " + (dir / "out" / "result.json").string() +
                 " -o " + (dir / "replay").string() + " -q --no-vtu");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const std::vector<double> replay = io::read_csv(dir / "replay" / "one-sided" / "steps.csv").values("edge_force"),
                            data = io::read_csv(dir / "experiment" / "one-sided" / "forces.csv").values("edge_force");
  ASSERT_EQ(replay.size(), data.size());
  for (std::size_t k = 0; k < data.size(); ++k) EXPECT_NEAR(replay[k], data[k], 1e-5 * std::abs(data[2])) << k;
  // A coefficient the law does not have is named with the file.
  std::ofstream(dir / "bad.json") << R"({"parameters": {"mu": 0.5, "lamda": 1.0}})";
  const auto b = run_tricot("simulate " + (dir / "project.toml").string() + " --law " + (dir / "bad.json").string() +
                            " -o " + (dir / "bad").string() + " -q");
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("bad.json: parameters.lamda: not a coefficient of the project's law; did you mean 'lambda'?"),
            std::string::npos)
      << b.err;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

TEST(StripWithAHole, NoisyDataOnACoarserMeshGiveTheTruthWithinItsStandardErrors) {
  const nlohmann::json r = identify(copy_example("strip_noisy"));
  for (const auto& [name, truth] : {std::pair<std::string, double>{"mu", 0.5}, {"lambda", 1.0}}) {
    const double value = r["parameters"][name].get<double>(), se = r["std_error"][name].get<double>();
    EXPECT_LT(std::abs(value - truth), kStandardErrors * se) << name << " = " << value << " ± " << se;
    EXPECT_LT(std::abs(value - truth), 5e-3 * truth) << name;
  }
  // σ scales every group: χ²/dof near 1 for a fit to the noise; the coarser mesh's own error adds a little.
  EXPECT_GT(r["chi2_per_dof"].get<double>(), 0.9);
  EXPECT_LT(r["chi2_per_dof"].get<double>(), 1.5);
}

// examples/two-pad (issue 28): the skin's μ and λ from a pad extensometer with a lesion of a known second
// material between the pads, plane strain, T6.
fs::path copy_two_pad(const std::string& name) {
  const fs::path dir = test::scratch_dir(name), from = test::source_dir() / "examples" / "two-pad";
  for (const char* f : {"pads.geo", "experiment.toml", "project.toml", "project-lesion.toml"})
    fs::copy_file(from / f, dir / f);
  return dir;
}

TEST(TwoPad, NoiseFreeDataOnTheTruthsMeshGiveTheSkinWithinATenthOfAPercent) {
  const fs::path dir = copy_two_pad("two_pad_noise_free");
  noise_free_on_the_projects_mesh(dir, "noise_edge_force = 0.002", "noise_field = 0.002", "size = 1.0", "size = 1.5");
  const nlohmann::json r = identify(dir);
  EXPECT_NEAR(r["parameters"]["mu"].get<double>(), 0.05, 1e-3 * 0.05);  // measured 1.1e-7
  EXPECT_NEAR(r["parameters"]["lambda"].get<double>(), 0.2, 1e-3 * 0.2);
}

TEST(TwoPad, NoisyDataOnACoarserMeshGiveTheSkinAndTheLesionWithinTwoStandardErrors) {
  const fs::path dir = copy_two_pad("two_pad_noisy");
  const nlohmann::json r = identify(dir);
  for (const auto& [name, truth] : {std::pair<std::string, double>{"mu", 0.05}, {"lambda", 0.2}}) {
    const double value = r["parameters"][name].get<double>(), se = r["std_error"][name].get<double>();
    EXPECT_LT(std::abs(value - truth), 2 * se) << name << " = " << value << " ± " << se;
  }
  const auto l =
      run_tricot("identify " + (dir / "project-lesion.toml").string() + " -o " + (dir / "lesion").string() + " -q");
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const nlohmann::json j = nlohmann::json::parse(text(dir / "lesion" / "result.json"));
  const double value = j["parameters"]["lesion.mu"].get<double>(), se = j["std_error"]["lesion.mu"].get<double>();
  EXPECT_LT(std::abs(value - 0.15), 2 * se) << value << " ± " << se;
}

}  // namespace
}  // namespace tricot
