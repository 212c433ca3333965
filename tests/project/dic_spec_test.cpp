// project/dic_spec.cpp: the [dic], [strain], [physical], [output] spec, its defaults and the engine
// settings it builds; each error once, at its key's origin.
#include "tricot/project/dic_spec.hpp"

#include <gtest/gtest.h>

#include "tricot/image/image.hpp"

namespace tricot::project {
namespace {

std::string message_of(const DicSpec& spec) {
  try {
    spec.settings(image::Image(200, 100));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DicSpec, TheSchemasDefaultsAreTheSpecsDefaults) {
  const DicSpec read = DicSpec::from_config(io::default_config(dic_schema()));
  const DicSpec code;
  EXPECT_EQ(read.sequence.dic.icgn.subset_size, code.sequence.dic.icgn.subset_size);
  EXPECT_EQ(read.sequence.dic.step, code.sequence.dic.step);
  EXPECT_EQ(read.sequence.mode, code.sequence.mode);
  EXPECT_EQ(read.sequence.dic.icgn.order, code.sequence.dic.icgn.order);
  EXPECT_EQ(read.sequence.dic.icgn.min_zncc, code.sequence.dic.icgn.min_zncc);
  EXPECT_EQ(read.sequence.update_loss, code.sequence.update_loss);
  EXPECT_EQ(read.sequence.strain.window, code.sequence.strain.window);
  EXPECT_EQ(read.physical.y_up, code.physical.y_up);
  EXPECT_EQ(read.output.panels, code.output.panels);
}

TEST(DicSpec, BuildsTheEnginesSettings) {
  DicSpec spec;
  spec.sequence.dic.icgn.subset_size = 21;
  spec.sequence.mode = dic::SequenceMode::automatic;
  spec.dic.seeds = {10, 20};
  spec.physical.mm_per_px = 0.1;
  const DicSettings s = spec.settings(image::Image(200, 100));
  EXPECT_EQ(s.sequence.dic.icgn.subset_size, 21);
  EXPECT_EQ(s.sequence.mode, dic::SequenceMode::automatic);
  ASSERT_EQ(s.sequence.dic.seeds.size(), 1u);
  EXPECT_EQ(s.sequence.dic.seeds[0], Vec2(10, 20));
  ASSERT_TRUE(s.outputs.physical.has_value());
  EXPECT_EQ(s.outputs.physical->centre_px, Vec2(99.5, 49.5));  // the image centre
}

TEST(DicSpec, OrderAutoAndAGaussianWindowReachTheEngineAndAWindowBelowOnePixelIsNamedByItsLine) {
  // Issue 16: dic.order = "auto" and dic.weight_sigma (0 = uniform, else 1 to 1000 px).
  const io::Node root = io::parse_config(dic_schema(), "[dic]\norder = \"auto\"\nweight_sigma = 7.5\n", "dic.toml");
  const DicSettings s = DicSpec::from_config(root).settings(image::Image(200, 100));
  EXPECT_EQ(s.sequence.dic.icgn.order, dic::ShapeOrder::automatic);
  EXPECT_EQ(s.sequence.dic.icgn.weight_sigma, 7.5);
  EXPECT_EQ(DicSpec{}.settings(image::Image(200, 100)).sequence.dic.icgn.weight_sigma, 0.0);
  // Issue 16: second order where it pays is tricot dic's default; first order is asked for by name.
  EXPECT_EQ(DicSpec{}.settings(image::Image(200, 100)).sequence.dic.icgn.order, dic::ShapeOrder::automatic);
  const io::Node first = io::parse_config(dic_schema(), "[dic]\norder = \"first\"\n", "dic.toml");
  EXPECT_EQ(DicSpec::from_config(first).settings(image::Image(200, 100)).sequence.dic.icgn.order,
            dic::ShapeOrder::first);
  const io::Node bad = io::parse_config(dic_schema(), "[dic]\nweight_sigma = 0.5\n", "dic.toml");
  EXPECT_EQ(message_of(DicSpec::from_config(bad)),
            "dic.toml:2: dic.weight_sigma: out of range (got 0.500000, expected 0 (uniform weights) or 1 to 1000 px)");
}

TEST(DicSpec, AnEvenSubsetIsNamedOnceByTheEnginesKey) {
  DicSpec spec;
  spec.sequence.dic.icgn.subset_size = 30;
  EXPECT_EQ(message_of(spec), "dic.subset_size: must be odd (got 30, expected an odd number of px from 7 to 301)");
  spec.dic.origin.set_by_flag("subset_size", "--subset");
  EXPECT_EQ(message_of(spec),
            "command line: --subset: must be odd (got 30, expected an odd number of px from 7 to 301)");
}

TEST(DicSpec, AnErrorOfAFileNamesItsLine) {
  const io::Node root = io::parse_config(dic_schema(), "[strain]\nwindow = 4\n", "dic.toml");
  EXPECT_EQ(message_of(DicSpec::from_config(root)),
            "dic.toml:2: strain.window: must be odd (got 4, expected an odd number from 3 to 51)");
}

TEST(DicSpec, ChecksWhatSpansKeys) {
  DicSpec spec;
  spec.dic.roi = {0, 0, 10, 10};
  spec.dic.roi_polygon = {0, 0, 10, 0, 0, 10};
  EXPECT_EQ(message_of(spec), "dic.roi: give only one of roi, roi_polygon and roi_mask");
  spec = DicSpec{};
  spec.dic.seeds = {1, 2, 3};
  EXPECT_EQ(message_of(spec), "dic.seeds: needs pairs of coordinates (got 3 numbers, expected [x0, y0, x1, y1, ...])");
}

}  // namespace
}  // namespace tricot::project
