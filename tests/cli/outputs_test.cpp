// Transactional outputs (issue 14, src/project/output/output_dir.cpp) through the verbs: a rerun into a
// folder that holds a different earlier run, killed before it publishes, leaves the earlier run whole
// (nothing of the rerun beside it); the rerun, completed, leaves only its own files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

#include "testing/cli.hpp"
#include "testing/outputs.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"
#include "tricot/synth/speckle.hpp"

namespace tricot {
namespace {

namespace fs = std::filesystem;
using test::expect_no_mix;
using test::run_tricot;
using test::write_file;

fs::path root_for(const std::string& name) {
  return test::scratch_dir("outputs_" + name + "_" + std::to_string(::getpid()));
}

TEST(Outputs, AKilledSimulateRerunLeavesNoMixAndARerunNoStaleSteps) {
  const fs::path root = root_for("simulate");
  write_file(root / "ten.toml", test::small_case(test::kTruthValues));  // 10 steps
  std::string four = test::small_case(test::kTruthValues);
  four.replace(four.find("steps = 10"), 10, "steps = 4");
  write_file(root / "four.toml", four);
  expect_no_mix(
      "simulate", root,
      [&](const fs::path& o) { return "simulate " + (root / "ten.toml").string() + " -q -o " + o.string(); },
      [&](const fs::path& o) { return "simulate " + (root / "four.toml").string() + " -q -o " + o.string(); });
  EXPECT_TRUE(fs::exists(root / "out" / "tension" / "step_0004.vtu"));
  EXPECT_FALSE(fs::exists(root / "out" / "tension" / "step_0005.vtu"));  // the earlier run's tenth step is gone
}

TEST(Outputs, AKilledSynthRerunLeavesNoMix) {
  const fs::path root = root_for("synth");
  write_file(root / "a.toml", test::small_experiment());
  write_file(root / "b.toml", test::small_experiment("nx = 2\nny = 4\nseed = 7\nnoise_relative = 0.01\n"));
  expect_no_mix(
      "synth", root, [&](const fs::path& o) { return "synth " + (root / "a.toml").string() + " -q -o " + o.string(); },
      [&](const fs::path& o) { return "synth " + (root / "b.toml").string() + " -q -o " + o.string(); });
}

// Speckle frames moved by (k, 0.5 k) px.
std::vector<fs::path> frames(const fs::path& dir, int n) {
  synth::SpeckleOptions o;
  o.subsamples = 1;
  const synth::SpecklePattern P(o, -20, -20, 140, 120);
  std::vector<fs::path> files;
  for (int k = 0; k < n; ++k) {
    const Vec2 d(k, 0.5 * k);
    const image::Image img = synth::render(P, 120, 100, [&](const Vec2& x) { return Vec2(x - d); });
    files.push_back(dir / ("frame_" + std::to_string(k) + ".png"));
    std::ofstream(files.back(), std::ios::binary) << image::encode_gray(img, ".png", 8);
  }
  return files;
}

TEST(Outputs, AKilledDicRerunLeavesNoMix) {
  const fs::path root = root_for("dic");
  const auto images = frames(root, 4);
  auto run = [&](int n, const fs::path& o) {
    std::string cmd = "dic -q --step 20 --roi 20,20,100,80 -o " + o.string();
    for (int k = 0; k < n; ++k) cmd += " " + images[k].string();
    return cmd;
  };
  expect_no_mix(
      "dic", root, [&](const fs::path& o) { return run(4, o); }, [&](const fs::path& o) { return run(2, o); });
  EXPECT_FALSE(fs::exists(root / "out" / "overlays" / "frame_0003.png"));  // the earlier run's last overlay
}

}  // namespace
}  // namespace tricot
