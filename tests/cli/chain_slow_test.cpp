// The experimental chain end to end: `tricot synth` renders camera images of a uniaxial Mooney–Rivlin
// test (FE solution, mirrored to the full specimen, speckle at the material points), `tricot dic`
// tracks points through them in incremental mode, and the tracked displacements, turned into mm by
// camera.json, match the FE displacement at the same material points.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>

#include "tricot/project/case_spec.hpp"
#include "tricot/project/synthesis.hpp"
#include "tricot/project/synth_images.hpp"
#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/files.hpp"
#include "tricot/synth/specimen.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;

// A 60 × 60 mm specimen, clamped grips pulled to 30 % overall strain in 6 steps: short and wide, so the
// field is far from uniform (the free edges neck, the clamps hold the ends' width). The camera sees
// 90 × 90 mm at 0.15 mm/px (600 × 600 px), the whole specimen and its grip lines, 8-bit, noise-free
// but for the 8-bit rounding.
constexpr const char* kExperiment = R"([mesh]
width = 60.0
height = 60.0
element = "Q8"
nx = 8
ny = 8

[law]
type = "mooney_rivlin"
[law.mooney_rivlin]
terms = ["C10", "C20", "C21", "C03"]
values = [0.1, -0.025, 0.015, 0.01]

[[test]]
name = "tension"
kind = "uniaxial"
control = "displacement"
load_max = 9.0
steps = 6

[synth]
field = false

[synth.images]
enabled = true
pixel_size = 0.15
width = 600
height = 600
speckle_size = 5.0
subsamples = 3
bits = 8
)";

// The region of interest: ±25 mm across and ±24 mm along the load in the reference (the edges are at
// ±30 mm); in the last frame the points reach ±31.5 mm of the grips' ±39 mm, and the subsets (31 px =
// 4.65 mm) stay on the specimen where its free edges neck.
constexpr const char* kRoi = "133,140,466,459";

// Tolerances, from the runs in docs/validation.md (the chain section) (272 points, 6 increments):
// - second-order subsets on noise-free 8-bit frames: RMS of |u_DIC − u_FE| 0.0020 px after the first
//   increment, 0.0029 px after the sixth, worst point 0.0082 px: what is left is 8-bit rounding and
//   interpolation, so the images show the FE field to a few thousandths of a pixel. 2× that still
//   catches any convention slip: the camera centre half a pixel off (in x and y) gives 0.029 px after
//   the first increment and 0.17 px after the sixth (measured); an unmirrored u or a flipped Y, tens of px.
constexpr double kSecondOrderRmsPx = 0.006;
constexpr double kSecondOrderMaxPx = 0.02;
// - first-order subsets (tricot dic's default before issue 16; pinned here) on the same frames: 0.0071 px RMS after one
// increment,   growing linearly to 0.028 px (worst 0.080 px): the affine subset's bias on a curved field, the same
//   in every increment, adds up. Bounds ~1.5× the measured values.
constexpr double kFirstOrderRmsPx = 0.04;
constexpr double kFirstOrderMaxPx = 0.12;
// - first-order, σ = 2 gray levels (of 255) of noise: that bias plus the noise's random error (which
//   grows as √k): 0.011 px after one increment, 0.034 px after six (worst 0.105 px). Bounds ~1.5×: the
//   noise is seeded, but DIC's path through it depends on floating-point details.
constexpr double kNoisyRmsPx = 0.05;
constexpr double kNoisyMaxPx = 0.16;
// Every point stays on the speckle and correlates (all 272 measured); allow a few to be given up.
constexpr double kOkFraction = 0.98;

struct Row {
  int frame = 0;
  Vec2 x0, u;
  bool ok = false;
};

std::vector<Row> read_points(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy,sigma_x,sigma_y");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::istringstream l(line);
    for (std::string cell; std::getline(l, cell, ',');) c.push_back(cell);
    Row r;
    r.frame = std::stoi(c.at(0));
    r.x0 = Vec2(std::stod(c.at(2)), std::stod(c.at(3)));
    r.ok = c.at(9) == "ok";
    if (r.ok) r.u = Vec2(std::stod(c.at(6)), std::stod(c.at(7)));
    rows.push_back(r);
  }
  return rows;
}

struct FrameError {
  int step = 0, ok = 0, points = 0;
  double rms = 0, max = 0;  ///< |u_DIC − u_FE| over the ok points, px
};

// A synthesized experiment and the FE solution its images were rendered from.
struct Synthesized {
  fs::path dir, images;
  CameraFile cam;
  fem::TestModel model;
  fem::SimulationResult sim;
  std::vector<synth::FullSpecimen> states;  ///< the full specimen at each frame
};

// `tricot synth` on kExperiment (+ `image_keys` in [synth.images]), and the same FE solve here (the same
// file, a deterministic solver: the same displacements).
std::unique_ptr<Synthesized> synthesize(const std::string& name, const std::string& image_keys) {
  auto x = std::make_unique<Synthesized>();
  x->dir = scratch_dir(name);
  const std::string text = std::string(kExperiment) + image_keys;
  io::write_atomic(x->dir / "experiment.toml", text);
  const auto s =
      run_tricot("synth " + (x->dir / "experiment.toml").string() + " -o " + (x->dir / "exp").string() + " -q");
  EXPECT_EQ(s.exit_code, 0) << s.err;
  x->images = x->dir / "exp" / "tension" / kImagesFolder;
  x->cam = read_camera(x->images);
  EXPECT_EQ(x->cam.frames.size(), 7u);
  // The last frame really is 30 % on: the grip's displacement is 2 × 9 mm over 60 mm.
  EXPECT_NEAR(x->cam.frames.back().edge_displacement, 9.0, 1e-9);

  const io::Node root = io::parse_config(synth_schema(), text, "experiment.toml");
  x->model = build_test(root.array("test")[0], root.section("mesh"));
  x->sim = fem::simulate(x->model, *build_law(root.section("law")), build_solver(root.section("solver")));
  EXPECT_TRUE(x->sim.usable()) << x->sim.message;
  for (const auto& f : x->cam.frames)
    x->states.emplace_back(x->model.mesh, f.step > 0 ? x->sim.steps.at(f.step - 1).u : Eigen::VectorXd());
  return x;
}

// Runs `tricot dic` (incremental, 31 px subsets every 20 px in kRoi, `dic_config` if any) on the
// frames and compares, per frame, the tracked displacements with the FE's at the same material points.
std::vector<FrameError> correlate(const Synthesized& x, const std::string& tag, const std::string& dic_config = "") {
  std::string files, config;
  for (const auto& f : x.cam.frames) files.append(" ").append((x.images / f.file).string());
  if (!dic_config.empty()) {
    io::write_atomic(x.dir / (tag + ".toml"), dic_config);
    config = std::string(" ").append((x.dir / (tag + ".toml")).string());
  }
  const fs::path out = x.dir / tag;
  const auto d = run_tricot("dic" + config + " --mode incremental --subset 31 --step 20 --roi " + kRoi + " -o " +
                            out.string() + " -q" + files);
  EXPECT_EQ(d.exit_code, 0) << d.err;

  std::vector<FrameError> e(x.cam.frames.size());
  const double s_mm = x.cam.camera.mm_per_px;
  for (const Row& r : read_points(out / "points.csv")) {
    FrameError& f = e.at(r.frame);
    ++f.points;
    if (!r.ok) continue;
    ++f.ok;
    // DIC (px, y down) → specimen mm (Y up) with the camera; FE at the tracked material point.
    const Vec2 X0 = x.cam.camera.to_specimen(r.x0);
    const Vec2 u_dic(s_mm * r.u(0), -s_mm * r.u(1));
    const auto u_fe = x.states[r.frame].displacement(X0);
    EXPECT_TRUE(u_fe.has_value()) << X0.transpose();
    const double err = u_fe ? (u_dic - *u_fe).norm() / s_mm : INFINITY;  // px
    f.rms += err * err;
    f.max = std::max(f.max, err);
  }
  for (std::size_t k = 0; k < e.size(); ++k) {
    FrameError& f = e[k];
    f.step = x.cam.frames[k].step;
    f.rms = std::sqrt(f.rms / std::max(f.ok, 1));
    std::printf("%s frame %zu (step %d): %d/%d ok, RMS %.4f px, max %.4f px\n", tag.c_str(), k, f.step, f.ok, f.points,
                f.rms, f.max);
  }
  return e;
}

void expect_within(const std::vector<FrameError>& e, double rms, double max, const std::string& what) {
  ASSERT_EQ(e.size(), 7u);
  for (std::size_t k = 1; k < e.size(); ++k) {
    ASSERT_GT(e[k].points, 250);
    EXPECT_GE(e[k].ok, kOkFraction * e[k].points) << what << ", frame " << k;
    EXPECT_LT(e[k].rms, rms) << what << ", frame " << k;
    EXPECT_LT(e[k].max, max) << what << ", frame " << k;
  }
}

TEST(Chain, DicOfNoiseFreeImagesMatchesTheFeDisplacementAtTrackedPoints) {
  const auto x = synthesize("chain", "");
  expect_within(correlate(*x, "dic_second", "[dic]\norder = \"second\"\n"), kSecondOrderRmsPx, kSecondOrderMaxPx,
                "second order");
  expect_within(correlate(*x, "dic_first", "[dic]\norder = \"first\"\n"), kFirstOrderRmsPx, kFirstOrderMaxPx,
                "first order");
  // Issue 16: tricot dic's default, order = "auto", takes second order where the curvature is significant,
  // which on noise-free frames is nearly everywhere: second order's bounds.
  expect_within(correlate(*x, "dic_auto"), kSecondOrderRmsPx, kSecondOrderMaxPx, "auto (the default)");
}

TEST(Chain, DicOfNoisyImagesMatchesTheFeDisplacementWithinTheNoiseError) {
  const auto x = synthesize("chain_noisy", "noise = 2.0\n");
  expect_within(correlate(*x, "dic_noisy", "[dic]\norder = \"first\"\n"), kNoisyRmsPx, kNoisyMaxPx,
                "first order, noise");
  // The default, auto: no worse than first order with the same noise (measured in docs/validation.md).
  expect_within(correlate(*x, "dic_noisy_auto"), kNoisyRmsPx, kNoisyMaxPx, "auto (the default), noise");
}

}  // namespace
}  // namespace tricot::project
