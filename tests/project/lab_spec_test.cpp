// project/spec/lab_spec.cpp: the lab file of `tricot experiment` as a typed spec — its defaults are the
// schema's, its paths are beside the file, and validate() names the key of each check across keys.
#include "tricot/project/lab_spec.hpp"

#include <gtest/gtest.h>

#include <string>

namespace tricot::project {
namespace {

LabSpec lab_spec(const std::string& text) {
  return LabSpec::from_config(io::parse_config(lab_schema(), text, "lab.toml"));
}

std::string message_of(const LabSpec& s) {
  try {
    s.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// A test of images that passes every check.
const std::string kImages =
    "[physical]\nmm_per_px = 0.1\n[[test]]\nimages = \"img\"\nlog = \"load.txt\"\ncamera_log = \"camera.csv\"\n";

TEST(LabSpec, TheSchemasDefaultsAreTheSpecsDefaults) {
  const LabSpec read = lab_spec("[[test]]\n");
  const LabTestSpec t;
  ASSERT_EQ(read.test.size(), 1u);
  const LabTestSpec& r = read.test[0];
  EXPECT_EQ(r.name, t.name);
  EXPECT_EQ(r.images, t.images);
  EXPECT_EQ(r.frame_times, t.frame_times);
  EXPECT_EQ(r.camera_file_column, t.camera_file_column);
  EXPECT_EQ(r.time_column, t.time_column);
  EXPECT_EQ(r.force_column, t.force_column);
  EXPECT_EQ(r.crosshead_column, t.crosshead_column);
  EXPECT_FALSE(r.clock_offset_s.has_value());
  EXPECT_FALSE(r.tare_N.has_value());
  EXPECT_EQ(r.width_mm, t.width_mm);
  EXPECT_EQ(r.free_length_mm, t.free_length_mm);
  EXPECT_FALSE(r.free_length_mm_given);
  EXPECT_EQ(r.direction, t.direction);
  EXPECT_EQ(r.tracks_format, t.tracks_format);
  EXPECT_EQ(r.tracks_unit, t.tracks_unit);
  EXPECT_FALSE(r.tracks_unit_given);
  EXPECT_EQ(r.x_column, t.x_column);
  EXPECT_EQ(r.sigma_tracks, t.sigma_tracks);
  EXPECT_EQ(r.frame_stride, t.frame_stride);
  EXPECT_EQ(r.model, t.model);
  EXPECT_EQ(r.force_scale, t.force_scale);
  const SyncSpec y;
  EXPECT_EQ(read.sync.max_offset_s, y.max_offset_s);
  EXPECT_EQ(read.sync.onset_fraction, y.onset_fraction);
  EXPECT_EQ(read.sync.crosshead_degree, y.crosshead_degree);
  EXPECT_EQ(read.sync.tare_margin_s, y.tare_margin_s);
  EXPECT_EQ(read.physical.scale_distance_mm, LabPhysicalSpec{}.scale_distance_mm);
  EXPECT_FALSE(read.physical.mm_per_px_given);
  EXPECT_FALSE(read.physical.scale_points_given);
}

TEST(LabSpec, PathsAreBesideTheFileAndGivenValuesAreKnownAsSuch) {
  const LabSpec s = LabSpec::from_config(io::parse_config(
      lab_schema(), "[[test]]\nimages = \"img\"\nlog = \"/data/load.txt\"\ntare_N = 0.5\nfree_length_mm = 80.0\n",
      "lab/lab.toml"));
  const LabTestSpec& t = s.test.at(0);
  EXPECT_EQ(t.images, std::filesystem::path("lab") / "img");
  EXPECT_EQ(t.log, std::filesystem::path("/data/load.txt"));
  EXPECT_TRUE(t.tracks.empty());
  EXPECT_EQ(t.tare_N, 0.5);
  EXPECT_FALSE(t.clock_offset_s.has_value());
  EXPECT_TRUE(t.free_length_mm_given);
  EXPECT_EQ(s.file, "lab/lab.toml");
  EXPECT_EQ(s.sync.options(t).tare_N, 0.5);
}

TEST(LabSpec, TheScaleIsMmPerPxOrTwoPointsAKnownDistanceApart) {
  EXPECT_EQ(lab_spec(kImages).physical.scale(), 0.1);
  const LabSpec points = lab_spec("[physical]\nscale_points = [0.0, 0.0, 30.0, 40.0]\nscale_distance_mm = 10.0\n");
  EXPECT_DOUBLE_EQ(points.physical.scale(), 0.2);
  const dic::PhysicalFrame f = points.physical.frame(101, 51);
  EXPECT_EQ(f.centre_px, Vec2(50, 25));  // [] = the image centre
}

TEST(LabSpec, AValidLabFilePasses) {
  EXPECT_EQ(message_of(lab_spec(kImages)), "no error");
  // Point tracks need no camera: a lab file of tracks only has no [physical].
  EXPECT_EQ(message_of(lab_spec("[[test]]\ntracks = \"t.csv\"\nframe_forces = \"f.csv\"\n")), "no error");
}

TEST(LabSpec, EachCheckAcrossKeysNamesItsFileLineAndKey) {
  EXPECT_EQ(message_of(lab_spec("[physical]\nmm_per_px = 0.1\n")),
            "lab.toml:1: test: no [[test]] table (expected one [[test]] per test)");
  EXPECT_EQ(message_of(lab_spec("[[test]]\ntracks = \"t.csv\"\n")),
            "lab.toml:1: test[0].frame_forces: a test of point tracks needs its per-frame force (got \"\", expected a "
            "CSV with a frame and a force column)");
  EXPECT_EQ(message_of(lab_spec("[[test]]\ntracks = \"t.csv\"\nframe_forces = \"f.csv\"\nclamps = [\"a\"]\n")),
            "lab.toml:4: test[0].clamps: two clamp markers: the fixed one and the pulled one (got 1 names, expected "
            "[A, B])");
  EXPECT_EQ(message_of(lab_spec(kImages + "frame_times = \"fps\"\n")),
            "lab.toml:3: test[0].fps: frame_times = \"fps\" needs a frame rate (got 0, expected fps > 0)");
  EXPECT_EQ(message_of(lab_spec("[physical]\nmm_per_px = 0.0\n" + kImages.substr(kImages.find("[[test]]")))),
            "lab.toml:2: physical.mm_per_px: a scale of zero: the pixel size must be > 0 (or give scale_points and "
            "scale_distance_mm) (got 0, expected mm_per_px > 0)");
  EXPECT_EQ(message_of(lab_spec("[experiment]\nfield_kind = \"incremental\"\n" + kImages + "hold_images = 2\n")),
            "lab.toml:5: test[0].setting_images: an incremental field of a test with setting images is not supported "
            "(its first step would count from the held setting, the model's from the reference) (got 2, expected "
            "field_kind = \"cumulative\")");
  EXPECT_EQ(message_of(lab_spec("[experiment]\nmodel = \"full\"\n" + kImages)).rfind("lab.toml:5: test[0].tracks: ", 0),
            0u);
}

}  // namespace
}  // namespace tricot::project
