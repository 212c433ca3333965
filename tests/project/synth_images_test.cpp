// `tricot synth` with [synth.images] (src/project/pipeline/synth_images.cpp): the frames, camera.json, and the
// errors of a bad table.
#include "tricot/project/synth_images.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "testing/experiment_case.hpp"
#include "tricot/project/experiment_files.hpp"
#include "testing/cli.hpp"
#include "testing/paths.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::run_tricot;
using test::scratch_dir;
using test::small_experiment;
using test::write_file;

// The small case's strip is 20 mm wide; 100 px at 0.5 mm/px show 50 mm, so the corners are background.
std::string images_table(const std::string& extra) {
  return "nx = 3\nny = 5\n\n[synth.images]\nenabled = true\npixel_size = 0.5\nwidth = 100\nheight = 80\n"
         "subsamples = 1\n" +
         extra;
}

test::CliRun synth(const fs::path& dir, const std::string& extra) {
  write_file(dir / "experiment.toml", small_experiment(images_table(extra)));
  return run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
}

TEST(SynthImages, WritesTheReferenceAndEveryNthStepWithTheirCamera) {
  const fs::path dir = scratch_dir("synth_images_frames");
  const auto r = synth(dir, "every_n_steps = 3\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path images = dir / "exp" / "tension" / kImagesFolder;
  const CameraFile cam = read_camera(images);
  EXPECT_EQ(cam.camera.mm_per_px, 0.5);
  EXPECT_EQ(cam.camera.centre_px(), Vec2(49.5, 39.5));
  ASSERT_EQ(cam.frames.size(), 4u);  // the reference, then steps 3, 6, 9 of 10
  const io::Table forces = io::read_csv(dir / "exp" / "tension" / kForcesFile);
  for (std::size_t j = 0; j < cam.frames.size(); ++j) {
    EXPECT_EQ(cam.frames[j].file, fmt::format("frame_{:04d}.png", j));
    EXPECT_EQ(cam.frames[j].step, int(3 * j));
    if (j > 0) {
      EXPECT_EQ(cam.frames[j].load, forces.rows[3 * j - 1][1]);
      EXPECT_EQ(cam.frames[j].edge_displacement, forces.rows[3 * j - 1][2]);
    }
  }
  EXPECT_FALSE(fs::exists(images / "frame_0004.png"));

  const image::LoadedImage f0 = image::load_image(images / "frame_0000.png");
  const image::LoadedImage f3 = image::load_image(images / "frame_0003.png");
  EXPECT_EQ(f0.bit_depth, 8);
  EXPECT_EQ(f0.image.width, 100);
  EXPECT_EQ(f0.image.height, 80);
  EXPECT_EQ(f0.image.at(0, 0), 128.0f);  // the flat background, 0.5 of 255, rounded
  EXPECT_EQ(f3.image.at(99, 79), 128.0f);
  double changed = 0;  // the strip stretches: the speckle under the centre moves
  for (int x = 40; x < 60; ++x) changed += std::abs(f0.image.at(x, 10) - f3.image.at(x, 10));
  EXPECT_GT(changed / 20, 10.0);
}

TEST(SynthImages, SixteenBitFramesLoadAsSixteenBit) {
  const fs::path dir = scratch_dir("synth_images_16");
  ASSERT_EQ(synth(dir, "bits = 16\nevery_n_steps = 10\n").exit_code, 0);
  const image::LoadedImage f = image::load_image(dir / "exp" / "tension" / kImagesFolder / "frame_0001.png");
  EXPECT_EQ(f.bit_depth, 16);
  EXPECT_EQ(f.image.at(0, 0), 32768.0f);  // 0.5 of 65535, rounded
}

TEST(SynthImages, FramesOfAnEarlierLongerRunAreRemoved) {
  const fs::path dir = scratch_dir("synth_images_stale");
  ASSERT_EQ(synth(dir, "every_n_steps = 2\n").exit_code, 0);
  const fs::path images = dir / "exp" / "tension" / kImagesFolder;
  EXPECT_TRUE(fs::exists(images / "frame_0005.png"));
  ASSERT_EQ(synth(dir, "every_n_steps = 5\n").exit_code, 0);
  EXPECT_TRUE(fs::exists(images / "frame_0002.png"));
  EXPECT_FALSE(fs::exists(images / "frame_0003.png"));
  EXPECT_EQ(read_camera(images).frames.size(), 3u);
}

TEST(SynthImages, ABitDepthOtherThan8Or16IsAConfigErrorAtItsLine) {
  const fs::path dir = scratch_dir("synth_images_bits");
  const auto r = synth(dir, "bits = 12\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("experiment.toml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("synth.images.bits"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "exp" / "tension")) << "nothing is written before the table is checked";
}

TEST(SynthImages, AnUnknownTextureIsAConfigErrorAtItsLine) {
  const fs::path dir = scratch_dir("synth_images_texture");
  const auto r = synth(dir, "texture = \"jersey\"\n");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("synth.images.texture"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("knit"), std::string::npos) << r.err;  // the choices are listed
}

// The knit texture differs from the speckle of the same seed, and camera.json says which one it is.
TEST(SynthImages, AKnitTextureIsRenderedAndRecorded) {
  const fs::path dir = scratch_dir("synth_images_knit");
  ASSERT_EQ(synth(dir / "knit", "texture = \"knit\"\n").exit_code, 0);
  ASSERT_EQ(synth(dir / "speckle", "").exit_code, 0);
  const auto frame = [&](const char* which) {
    return image::load_image(dir / which / "exp" / "tension" / kImagesFolder / "frame_0000.png").image;
  };
  const image::Image knit = frame("knit"), speckle = frame("speckle");
  double diff = 0;
  for (std::size_t i = 0; i < knit.pixels.size(); ++i) diff += std::abs(knit.pixels[i] - speckle.pixels[i]);
  EXPECT_GT(diff / knit.pixels.size(), 0.02) << "mean absolute difference, fraction of full scale";
  const std::string camera = io::read_text(dir / "knit" / "exp" / "tension" / kImagesFolder / kCameraFile);
  EXPECT_NE(camera.find("\"texture\": \"knit\""), std::string::npos) << camera;
}

TEST(SynthImages, NoImagesUnlessEnabled) {
  const fs::path dir = scratch_dir("synth_images_off");
  write_file(dir / "experiment.toml", small_experiment());
  ASSERT_EQ(
      run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q").exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "exp" / "tension" / kForcesFile));
  EXPECT_FALSE(fs::exists(dir / "exp" / "tension" / kImagesFolder));
}

std::string message_of(const SynthImagesSpec& s) {
  try {
    s.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SynthImagesSpec, TheSchemasDefaultsAreTheSpecsDefaults) {
  const SynthImagesSpec read = SynthImagesSpec::from_config(
      io::default_config(io::SectionSpec{"", "", false, {}, {synth_images_section()}}).section("images"));
  const SynthImagesSpec code;
  EXPECT_EQ(read.enabled, code.enabled);
  EXPECT_EQ(read.pixel_size, code.pixel_size);
  EXPECT_EQ(read.width, code.width);
  EXPECT_EQ(read.height, code.height);
  EXPECT_EQ(read.speckle_size, code.speckle_size);
  EXPECT_EQ(read.coverage, code.coverage);
  EXPECT_EQ(read.subsamples, code.subsamples);
  EXPECT_EQ(read.background, code.background);
  EXPECT_EQ(read.noise, code.noise);
  EXPECT_EQ(read.bits, code.bits);
  EXPECT_EQ(read.every_n_steps, code.every_n_steps);
  EXPECT_EQ(message_of(code), "no error");
}

TEST(SynthImagesSpec, ABadValueBuiltInCodeNamesItsKeyValueAndRange) {
  SynthImagesSpec s;
  s.width = 4;
  EXPECT_EQ(message_of(s), "synth.images.width: out of range (got 4, expected 8 to 20000)");
  s = {};
  s.background = 1.5;
  EXPECT_EQ(message_of(s), "synth.images.background: out of range (got 1.5, expected 0 to 1)");
  s = {};
  s.bits = 12;
  EXPECT_EQ(message_of(s), "synth.images.bits: PNG files are 8 or 16 bit (got 12, expected 8 or 16)");
}

TEST(SynthImagesSpec, ItsOptionsAreTheRenderersInItsUnits) {
  SynthImagesSpec s;
  s.speckle_size = 6;
  s.pixel_size = 0.25;
  const synth::SpecimenImageOptions o = s.options(7);
  EXPECT_EQ(o.speckle.radius, 3.0);  // speckle_size is twice the blob radius
  EXPECT_EQ(o.camera.mm_per_px, 0.25);
  EXPECT_EQ(o.speckle.seed, 7u);
}

// A rig test (issue 13): the setting in frames of its own, the held setting, then the pull (set, hold,
// pull), each frame's phase in camera.json; the setting frames show the knit's shrinkage load.
TEST(SynthImages, ARigTestShowsItsSettingAndHoldBeforeThePull) {
  const fs::path dir = scratch_dir("synth_images_rig");
  write_file(dir / "experiment.toml", R"([mesh]
element = "Q8"
nx = 3
ny = 3

[law]
type = "reference_fabric"

[rig]
setting_steps = 2

[synth]
nx = 2
ny = 2

[synth.images]
enabled = true
pixel_size = 0.5
width = 96
height = 96
subsamples = 1
hold_frames = 1

[[test]]
name = "rig"
kind = "rig"
side = 30.0
pull = "wale"
transverse_strain = 0.3
pull_strain = 0.3
steps = 3
)");
  const auto r = run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const CameraFile cam = read_camera(dir / "exp" / "rig" / kImagesFolder);
  ASSERT_EQ(cam.frames.size(), 7u);  // reference, 2 setting, 1 hold, 3 pull
  EXPECT_EQ(cam.setting_frames(), 2);
  EXPECT_EQ(cam.hold_frames(), 1);
  const std::vector<std::string> phases{"reference", "setting", "setting", "hold", "pull", "pull", "pull"};
  const std::vector<int> steps{0, 0, 0, 0, 1, 2, 3}, settings{0, 1, 2, 2, 2, 2, 2};
  const io::Table forces = io::read_csv(dir / "exp" / "rig" / kForcesFile);
  for (std::size_t j = 0; j < cam.frames.size(); ++j) {
    EXPECT_EQ(cam.frames[j].phase, phases[j]) << j;
    EXPECT_EQ(cam.frames[j].step, steps[j]) << j;
    EXPECT_EQ(cam.frames[j].setting, settings[j]) << j;
    if (j < 4) EXPECT_EQ(cam.frames[j].edge_displacement, 0.0) << j;  // the grip at rest
    else EXPECT_EQ(cam.frames[j].edge_displacement, forces.rows[j - 4][2]) << j;
  }
  // The hold frame shows the last setting state: the same image but for the camera noise (none here).
  EXPECT_EQ(io::read_text(dir / "exp" / "rig" / kImagesFolder / "frame_0002.png"),
            io::read_text(dir / "exp" / "rig" / kImagesFolder / "frame_0003.png"));
  EXPECT_NE(io::read_text(dir / "exp" / "rig" / kImagesFolder / "frame_0001.png"),
            io::read_text(dir / "exp" / "rig" / kImagesFolder / "frame_0002.png"));
}

}  // namespace
}  // namespace tricot::project
