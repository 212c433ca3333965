// `tricot dic` from the outside (docs/design.md): outputs, flags over the config, and every bad input
// ending in a clear one-line error with the documented exit code, or in per-point statuses.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tricot/project/dic_spec.hpp"
#include "testing/cli.hpp"
#include "testing/meshio.hpp"
#include "tricot/dic/grid.hpp"
#include "tricot/image/image.hpp"
#include "tricot/synth/speckle.hpp"

using namespace tricot;
using test::run_tricot;
namespace fs = std::filesystem;

namespace {

/// Noise-free rendered frames: the measured translation is within a few thousandths of a pixel.
constexpr double kShiftTol = 0.01;

constexpr int kW = 160, kH = 120;

/// Writes a speckle frame moved by `d` (px) to `path`; `blank_left` px of the left side are flat gray.
void write_frame(const fs::path& path, const Vec2& d, int blank_left = 0, int w = kW, int h = kH) {
  synth::SpeckleOptions o;
  o.subsamples = 1;
  const synth::SpecklePattern P(o, -20, -20, w + 20, h + 20);
  image::Image img = synth::render(P, w, h, [&](const Vec2& x) { return Vec2(x - d); });
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < blank_left; ++x) img.at(x, y) = 0.5f;
  std::ofstream(path, std::ios::binary) << image::encode_gray(img, path.extension().string(), 8);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::vector<std::string>> read_rows(const fs::path& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(csv));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream l(line);
    while (std::getline(l, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

std::string q(const fs::path& p) { return std::string("'").append(p.string()).append("'"); }

std::string first_line(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  return line;
}

/// Subsets 20 px from the border stay inside the image for the shifts of Frames.
constexpr const char* kRoi = " --roi 20,20,140,100";

/// Three frames translated by 0, (1.5, −0.5) and (3, −1) px.
struct Frames {
  fs::path dir;
  std::vector<fs::path> files;
  explicit Frames(const std::string& name) : dir(test::scratch_dir(name)) {
    const Vec2 d[3] = {{0, 0}, {1.5, -0.5}, {3, -1}};
    for (int k = 0; k < 3; ++k) {
      files.push_back(dir / ("frame_" + std::to_string(k) + ".png"));
      write_frame(files.back(), d[k]);
    }
  }
  std::string args() const {
    std::string s;
    for (const auto& f : files) s.append(" ").append(q(f));
    return s;
  }
};

}  // namespace

TEST(CliDic, HelpTeachesWithExamplesAndTheOutputs) {
  const auto r = run_tricot("dic --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"Examples:", "tricot dic -o out/dic", "points.csv", "--subset", "--step", "--mode", "--roi",
                        "incremental", "Exit codes"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

TEST(CliDic, PrintConfigIsAFullyCommentedFileThatReadsBackAsTheDefaults) {
  const auto r = run_tricot("dic --print-config");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("[dic]"), std::string::npos);
  EXPECT_NE(r.out.find("# Subset size"), std::string::npos);
  const io::Node n = io::parse_config(project::dic_schema(), r.out, "printed");
  EXPECT_EQ(n.section("dic").integer("subset_size"), 31);
  EXPECT_EQ(n.section("dic").string("mode"), "incremental");
}

TEST(CliDic, WritesPointsCsvWithTheDesignColumnsFrameZeroAsReferenceAndOverlays) {
  const Frames f("cli_dic_points");
  const fs::path out = f.dir / "out";
  const auto r = run_tricot("dic -q --step 20" + std::string(kRoi) + " -o " + q(out) + f.args());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = read_rows(out / "points.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(first_line(out / "points.csv"), "frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy,sigma_x,sigma_y");
  const std::size_t n = dic::make_grid(dic::Roi::rectangle(20, 20, 140, 100), kW, kH, 31, 20).size();
  ASSERT_EQ(rows.size(), 1 + 3 * n);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto& c = rows[i];
    ASSERT_EQ(c.size(), 15u) << i;
    const int frame = std::stoi(c[0]);
    EXPECT_EQ(c[9], "ok") << i;
    const double u = std::stod(c[6]), v = std::stod(c[7]);
    EXPECT_NEAR(u, 1.5 * frame, kShiftTol) << i;
    EXPECT_NEAR(v, -0.5 * frame, kShiftTol) << i;
    EXPECT_NEAR(std::stod(c[4]) - std::stod(c[2]), u, 1e-4);  // u = x − x0
    if (frame == 0) {
      EXPECT_EQ(c[8], "1.000000");
      EXPECT_EQ(std::stod(c[13]), 0.0);  // the reference has no error
    } else {
      EXPECT_GT(std::stod(c[13]), 0.0) << i;  // IC-GN's σ of a matched point
      EXPECT_GT(std::stod(c[14]), 0.0) << i;
    }
  }
  const auto frames = read_rows(out / "frames.csv");
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0][0], "frame");
  EXPECT_EQ(frames[3][1], f.files[2].string());
  // overlay_every = 10 (default): the reference and the last frame
  EXPECT_TRUE(fs::exists(out / "overlays" / "frame_0000.png"));
  EXPECT_FALSE(fs::exists(out / "overlays" / "frame_0001.png"));
  EXPECT_TRUE(fs::exists(out / "overlays" / "frame_0002.png"));
  EXPECT_NE(r.out.find("3 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("strains: virtual strain gauge "), std::string::npos) << r.out;  // issue 16
}

TEST(CliDic, FlagsOverrideTheConfigFile) {
  const Frames f("cli_dic_flags");
  std::ofstream(f.dir / "dic.toml")
      << "[dic]\nsubset_size = 41\nstep = 40\nmode = \"reference\"\n\n[output]\noverlays = false\n";
  const fs::path out = f.dir / "out";
  const auto r = run_tricot("dic " + q(f.dir / "dic.toml") + " -q --step 15 -o " + q(out) + f.args());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t n = dic::make_grid(dic::Roi::whole_image(), kW, kH, 41, 15).size();  // subset from the file
  EXPECT_EQ(read_rows(out / "points.csv").size(), 1 + 3 * n);
  EXPECT_EQ(read_rows(out / "frames.csv")[3][2], "0");  // reference mode from the file
  // Issue 16: the strains' virtual strain gauge, (window − 1) × step + subset = 4 × 15 + 41 px.
  EXPECT_EQ(read_rows(out / "frames.csv")[0][7], "vsg_px");
  EXPECT_EQ(read_rows(out / "frames.csv")[3][7], "101");
  EXPECT_FALSE(fs::exists(out / "overlays"));
}

TEST(CliDic, AMissingFrameExitsThreeNamingItBeforeAnyWork) {
  const Frames f("cli_dic_missing");
  const fs::path out = f.dir / "out";
  const auto r = run_tricot("dic -q -o " + q(out) + f.args() + " " + q(f.dir / "frame_9.png"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.err, "tricot: error: " + (f.dir / "frame_9.png").string() + ": image not found\n");
  EXPECT_FALSE(fs::exists(out / "points.csv"));
}

TEST(CliDic, AFrameOfAnotherSizeExitsThreeNamingItAndBothSizes) {
  const Frames f("cli_dic_size");
  write_frame(f.dir / "big.png", Vec2(1, 0), 0, kW + 1, kH);
  const auto r = run_tricot("dic -q -o " + q(f.dir / "out") + f.args() + " " + q(f.dir / "big.png"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find((f.dir / "big.png").string() +
                       ": image size differs from the reference image (got 161x120, expected 160x120)"),
            std::string::npos)
      << r.err;
}

TEST(CliDic, ABlankReferenceIsAnErrorNamingTheFile) {
  const Frames f("cli_dic_blank_ref");
  std::ofstream(f.dir / "blank.png", std::ios::binary) << image::encode_gray(image::Image(kW, kH, 0.5f, 1.0), ".png");
  const auto r = run_tricot("dic -q -o " + q(f.dir / "out") + " " + q(f.dir / "blank.png") + f.args());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(
      r.err.find((f.dir / "blank.png").string() + ": the reference image has no texture in the region of interest"),
      std::string::npos)
      << r.err;
}

TEST(CliDic, ABlankFrameLosesEveryPointWritesTheResultsAndExitsFour) {
  const Frames f("cli_dic_blank_frame");
  std::ofstream(f.dir / "blank.png", std::ios::binary) << image::encode_gray(image::Image(kW, kH, 0.5f, 1.0), ".png");
  const fs::path out = f.dir / "out";
  const auto r = run_tricot("dic -q --step 20 -o " + q(out) + " " + q(f.files[0]) + " " + q(f.dir / "blank.png") + " " +
                            q(f.files[1]));
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("blank.png: every point was lost"), std::string::npos) << r.err;
  const auto rows = read_rows(out / "points.csv");
  int frame1 = 0, frame2 = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i][0] == "1") {
      ++frame1;
      EXPECT_NE(rows[i][9], "ok");
      EXPECT_EQ(rows[i][4], "");  // no position
    }
    if (rows[i][0] == "2") {
      ++frame2;
      EXPECT_EQ(rows[i][9], "lost");
    }
  }
  EXPECT_GT(frame1, 0);
  EXPECT_EQ(frame1, frame2);
}

TEST(CliDic, ARoiOutsideTheImageIsAUsageErrorNamingTheFlag) {
  const Frames f("cli_dic_roi");
  const auto r = run_tricot("dic -q --roi 500,500,600,600 -o " + q(f.dir / "out") + f.args());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "tricot: error: command line: --roi: the rectangle reaches outside the image (got [500, 500, 600, 600], "
            "expected within the 160x120 reference image: 0 <= x <= 159, 0 <= y <= 119)\n");
}

TEST(CliDic, ARoiFlagThatIsNotFourNumbersIsAUsageError) {
  const Frames f("cli_dic_roi_text");
  const auto r = run_tricot("dic -q --roi 1,2,3 -o " + q(f.dir / "out") + f.args());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--roi: not four numbers"), std::string::npos) << r.err;
}

TEST(CliDic, AnEvenSubsetIsAUsageErrorNamingTheFlag) {
  const Frames f("cli_dic_even");
  const auto r = run_tricot("dic -q --subset 30 -o " + q(f.dir / "out") + f.args());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--subset: must be odd (got 30"), std::string::npos) << r.err;
}

TEST(CliDic, ABadConfigValueNamesFileLineAndKey) {
  const Frames f("cli_dic_bad_config");
  std::ofstream(f.dir / "dic.toml") << "[dic]\nstep = 10\nmin_zncc = 1.5\n";
  const auto r = run_tricot("dic " + q(f.dir / "dic.toml") + " -q -o " + q(f.dir / "out") + f.args());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tricot: error: " + (f.dir / "dic.toml").string() +
                       ":3: dic.min_zncc: out of range (got 1.5, expected 0 to 1)\n");
}

TEST(CliDic, ASeedOnABlankAreaStillMeasuresTheTexturedPartWithPerPointStatuses) {
  const fs::path dir = test::scratch_dir("cli_dic_seed");
  write_frame(dir / "a.png", Vec2(0, 0), 70);
  write_frame(dir / "b.png", Vec2(1.25, 0.5), 70);
  std::ofstream(dir / "dic.toml") << "[dic]\nstep = 10\nseeds = [20.0, 60.0]\n";
  const fs::path out = dir / "out";
  const auto r =
      run_tricot("dic " + q(dir / "dic.toml") + " -q -o " + q(out) + " " + q(dir / "a.png") + " " + q(dir / "b.png"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int blank = 0, ok = 0;
  for (const auto& c : read_rows(out / "points.csv")) {
    if (c[0] != "1") continue;
    const double x0 = std::stod(c[2]);
    if (x0 + 15 < 70) {
      ++blank;
      EXPECT_EQ(c[9], "no_texture") << x0;
    }
    if (x0 - 15 > 70) {
      ++ok;
      ASSERT_EQ(c[9], "ok") << x0;
      EXPECT_NEAR(std::stod(c[6]), 1.25, kShiftTol);
    }
  }
  EXPECT_GT(blank, 0);
  EXPECT_GT(ok, 0);
}

TEST(CliDic, IncrementsAndSpecimenCoordinatesAreWrittenOnRequest) {
  const Frames f("cli_dic_extra");
  std::ofstream(f.dir / "dic.toml")
      << "[dic]\nstep = 20\nroi = [20, 20, 140, 100]\n\n[physical]\nmm_per_px = 0.1\ncentre_px = [80.0, 60.0]\n\n"
         "[output]\nincrements = true\noverlays = false\n";
  const fs::path out = f.dir / "out";
  const auto r = run_tricot("dic " + q(f.dir / "dic.toml") + " -q -o " + q(out) + f.args());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto inc = read_rows(out / "increments.csv");
  ASSERT_GT(inc.size(), 1u);
  EXPECT_EQ(first_line(out / "increments.csv"), "from,to,id,x,y,u,v,zncc,status,sigma_x,sigma_y");
  for (std::size_t i = 1; i < inc.size(); ++i)
    EXPECT_NEAR(std::stod(inc[i][5]), 1.5, kShiftTol);  // each step moves 1.5 px
  const auto sp = read_rows(out / "specimen.csv");
  EXPECT_EQ(sp[0][2], "X0");
  for (std::size_t i = 1; i < sp.size(); ++i) {
    if (sp[i][0] != "2") continue;
    // 0.1 mm/px; specimen Y up: image v = −1 px is +0.1 mm
    EXPECT_NEAR(std::stod(sp[i][6]), 0.3, 0.1 * kShiftTol);
    EXPECT_NEAR(std::stod(sp[i][7]), 0.1, 0.1 * kShiftTol);
  }
}

TEST(CliDic, APolygonOrAMaskFromTheConfigLimitsTheGrid) {
  const Frames f("cli_dic_shapes");
  // the mask (relative to the config file) keeps x ≥ 80; the polygon a triangle
  image::Image mask(kW, kH, 0.0f, 255.0);
  for (int y = 0; y < kH; ++y)
    for (int x = 80; x < kW; ++x) mask.at(x, y) = 255;
  std::ofstream(f.dir / "mask.png", std::ios::binary) << image::encode_gray(mask, ".png");
  std::ofstream(f.dir / "mask.toml") << "[dic]\nstep = 10\nroi_mask = \"mask.png\"\n[output]\noverlays = false\n";
  std::ofstream(f.dir / "poly.toml")
      << "[dic]\nstep = 10\nroi_polygon = [20, 20, 140, 20, 20, 100]\n[output]\noverlays = false\n";
  const auto m = run_tricot("dic " + q(f.dir / "mask.toml") + " -q -o " + q(f.dir / "m") + f.args());
  ASSERT_EQ(m.exit_code, 0) << m.err;
  const auto p = run_tricot("dic " + q(f.dir / "poly.toml") + " -q -o " + q(f.dir / "p") + f.args());
  ASSERT_EQ(p.exit_code, 0) << p.err;
  const auto mask_rows = read_rows(f.dir / "m" / "points.csv"), poly_rows = read_rows(f.dir / "p" / "points.csv");
  ASSERT_GT(mask_rows.size(), 1u);
  ASSERT_GT(poly_rows.size(), 1u);
  for (std::size_t i = 1; i < mask_rows.size(); ++i) EXPECT_GE(std::stod(mask_rows[i][2]), 80.0);
  for (std::size_t i = 1; i < poly_rows.size(); ++i) {
    const double x = std::stod(poly_rows[i][2]), y = std::stod(poly_rows[i][3]);
    EXPECT_LE((x - 20) / 120 + (y - 20) / 80, 1.0 + 1e-9) << x << "," << y;  // inside the triangle
  }
}

TEST(CliDic, NoImageIsAUsageError) {
  const fs::path dir = test::scratch_dir("cli_dic_none");
  EXPECT_EQ(run_tricot("dic -o " + q(dir / "out")).exit_code, 2);
}

namespace {

/// `n` frames, frame k translated by (0.5 k, −0.25 k) px.
std::vector<fs::path> moving_frames(const fs::path& dir, int n) {
  std::vector<fs::path> files;
  for (int k = 0; k < n; ++k) {
    files.push_back(dir / ("f_" + std::to_string(k) + ".png"));
    write_frame(files.back(), Vec2(0.5 * k, -0.25 * k));
  }
  return files;
}

std::string args_of(const std::vector<fs::path>& files) {
  std::string s;
  for (const auto& f : files) s.append(" ").append(q(f));
  return s;
}

/// frames.csv without its seconds column (wall time differs from run to run).
std::string frames_without_seconds(const fs::path& csv) {
  std::string s;
  for (const auto& row : read_rows(csv)) {
    for (std::size_t c = 0; c < row.size(); ++c)
      if (c != 6) s += row[c] + ",";  // 6: seconds (then vsg_px, issue 16)
    s += "\n";
  }
  return s;
}

}  // namespace

TEST(CliDic, FieldsAreOneCompressedVtuPerFrameAndAPvdSeriesThatMeshioReadsBack) {
  const fs::path dir = test::scratch_dir("cli_dic_fields");
  const auto files = moving_frames(dir, 3);
  const fs::path out = dir / "out";
  const auto r = run_tricot("dic -q --step 20" + std::string(kRoi) + " -o " + q(out) + args_of(files));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string pvd = slurp(out / "fields.pvd");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NE(pvd.find("fields/frame_000" + std::to_string(k) + ".vtu"), std::string::npos) << pvd;
    EXPECT_NE(slurp(out / "fields" / ("frame_000" + std::to_string(k) + ".vtu")).find("vtkZLibDataCompressor"),
              std::string::npos);
  }
  if (!test::have_meshio()) GTEST_SKIP() << "python3 with meshio is not installed";
  const std::size_t n = dic::make_grid(dic::Roi::rectangle(20, 20, 140, 100), kW, kH, 31, 20).size();
  // Frame 2 moved by (1, −0.5) px: every ok point (status 0) reads it back, frame 0 reads 0.
  const std::string got = test::read_with_meshio(out / "fields" / "frame_0002.vtu", R"(
import numpy as np
d = m.point_data["displacement"]; s = m.point_data["status"]
ok = s == 0
print(len(m.points), int(ok.sum()), len(m.cells_dict["quad"]))
print("%.4f %.4f %.4f" % (np.abs(d[ok, 0] - 1.0).max(), np.abs(d[ok, 1] + 0.5).max(),
                          np.nanmax(np.abs(m.point_data["exx"]))))
print(int(np.asarray(m.field_data["vsg_px"]).ravel()[0]))
)");
  std::istringstream in(got);
  std::size_t points = 0, ok = 0, quads = 0;
  double du = 1, dv = 1, exx = 1;
  int vsg = 0;
  in >> points >> ok >> quads >> du >> dv >> exx >> vsg;
  EXPECT_EQ(vsg, 4 * 20 + 31) << got;  // issue 16: the virtual strain gauge as field data
  EXPECT_EQ(points, n) << got;
  EXPECT_EQ(ok, n) << got;
  EXPECT_GT(quads, 0u) << got;
  EXPECT_LT(du, kShiftTol) << got;
  EXPECT_LT(dv, kShiftTol) << got;
  EXPECT_LT(exx, 1e-3) << got;  // a rigid translation: no strain
}

TEST(CliDic, FieldsCanBeTurnedOffOrWrittenEveryNthFrame) {
  const fs::path dir = test::scratch_dir("cli_dic_fields_every");
  const auto files = moving_frames(dir, 4);
  std::ofstream(dir / "every.toml") << "[output]\noverlays = false\nfields_every = 2\n";
  std::ofstream(dir / "off.toml") << "[output]\nfields = false\n";
  ASSERT_EQ(
      run_tricot("dic " + q(dir / "every.toml") + " -q --step 20" + kRoi + " -o " + q(dir / "every") + args_of(files))
          .exit_code,
      0);
  EXPECT_TRUE(fs::exists(dir / "every" / "fields" / "frame_0000.vtu"));
  EXPECT_FALSE(fs::exists(dir / "every" / "fields" / "frame_0001.vtu"));
  EXPECT_TRUE(fs::exists(dir / "every" / "fields" / "frame_0002.vtu"));
  EXPECT_TRUE(fs::exists(dir / "every" / "fields" / "frame_0003.vtu"));  // the last frame always
  EXPECT_FALSE(fs::exists(dir / "every" / "overlays"));
  ASSERT_EQ(run_tricot("dic " + q(dir / "off.toml") + " -q --step 20" + kRoi + " -o " + q(dir / "off") + args_of(files))
                .exit_code,
            0);
  EXPECT_FALSE(fs::exists(dir / "off" / "fields"));
  EXPECT_FALSE(fs::exists(dir / "off" / "fields.pvd"));
  EXPECT_TRUE(fs::exists(dir / "off" / "points.csv"));
}

// A run killed in the middle of writing a frame publishes nothing; --resume goes on from the last
// complete frame and leaves the same files as a run that was never killed.
TEST(CliDic, AResumedKilledRunEqualsTheUninterruptedOne) {
  const fs::path dir = test::scratch_dir("cli_dic_resume");
  const auto files = moving_frames(dir, 6);
  std::ofstream(dir / "c.toml") << "[output]\noverlay_every = 2\nincrements = true\n[physical]\nmm_per_px = 0.05\n";
  for (const char* mode : {"incremental", "reference", "auto"}) {
    SCOPED_TRACE(mode);
    const std::string common = "dic " + q(dir / "c.toml") + " -q --step 20 --mode " + mode + kRoi + args_of(files);
    const fs::path whole = dir / (std::string("whole_") + mode), killed = dir / (std::string("killed_") + mode);
    ASSERT_EQ(run_tricot(common + " -o " + q(whole)).exit_code, 0);

    ::setenv("TRICOT_TEST_KILL_DIC_FRAME", "3", 1);
    const auto k = run_tricot(common + " -o " + q(killed));
    ::unsetenv("TRICOT_TEST_KILL_DIC_FRAME");
    ASSERT_NE(k.exit_code, 0);
    EXPECT_FALSE(fs::exists(killed / "points.csv")) << "a killed run published a file";

    const auto r = run_tricot(common + " --resume -o " + q(killed));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("resuming from frame 3"), std::string::npos) << r.out;
    for (const char* f : {"points.csv", "increments.csv", "specimen.csv", "fields.pvd", "fields/frame_0004.vtu",
                          "fields/frame_0005.vtu", "overlays/frame_0004.png"})
      EXPECT_EQ(slurp(killed / f), slurp(whole / f)) << f;
    EXPECT_EQ(frames_without_seconds(killed / "frames.csv"), frames_without_seconds(whole / "frames.csv"));
    EXPECT_FALSE(fs::exists(killed / ".tricot-dic"));
  }
}

TEST(CliDic, ResumingWithOtherSettingsIsAUsageErrorAndWithoutACheckpointStartsAtFrameZero) {
  const fs::path dir = test::scratch_dir("cli_dic_resume_other");
  const auto files = moving_frames(dir, 4);
  const fs::path out = dir / "out";
  ::setenv("TRICOT_TEST_KILL_DIC_FRAME", "2", 1);
  ASSERT_NE(run_tricot("dic -q --step 20" + std::string(kRoi) + " -o " + q(out) + args_of(files)).exit_code, 0);
  ::unsetenv("TRICOT_TEST_KILL_DIC_FRAME");
  const auto other = run_tricot("dic -q --step 10" + std::string(kRoi) + " --resume -o " + q(out) + args_of(files));
  EXPECT_EQ(other.exit_code, 2) << other.err;
  EXPECT_NE(other.err.find("--resume"), std::string::npos) << other.err;

  const fs::path fresh = dir / "fresh";
  const auto r = run_tricot("dic -q --step 20" + std::string(kRoi) + " --resume -o " + q(fresh) + args_of(files));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("nothing to resume"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(fresh / "points.csv"));
}

// Off a terminal (this test's pipes), progress is one log line per frame, no carriage returns.
TEST(CliDic, OffATerminalProgressIsOneLinePerFrame) {
  const Frames f("cli_dic_log_lines");
  const auto r = run_tricot("dic --step 20" + std::string(kRoi) + " -o " + q(f.dir / "out") + f.args());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << r.err;
  for (const char* line : {"dic: frame 1: ", "dic: frame 2: "}) {
    const auto at = r.err.find(line);
    ASSERT_NE(at, std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(line, at + 1), std::string::npos) << "twice: " << r.err;
  }
  EXPECT_NE(r.err.find("(2/2)"), std::string::npos) << r.err;
}
