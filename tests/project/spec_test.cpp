// project/spec.cpp: where a key of a spec came from, so that one error names the file and line, the
// command-line flag, or (a spec built in code) the dotted key alone.
#include "tricot/project/spec.hpp"

#include <gtest/gtest.h>

#include <functional>

namespace tricot::project {
namespace {

io::SectionSpec schema() {
  io::SectionSpec dic{"dic", "", false, {io::key("step", std::int64_t{10}, "grid step", 1, 1000)}, {}};
  return io::SectionSpec{"", "", false, {}, {dic}};
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Origin, OfATableBuiltInCodeNamesTheDottedKey) {
  const Origin o("dic");
  EXPECT_EQ(o.where("step").key, "dic.step");
  EXPECT_EQ(o.where("step").file, "");
  EXPECT_EQ(message_of([&] { o.fail("step", "too coarse", "40", "< 20"); }),
            "dic.step: too coarse (got 40, expected < 20)");
}

TEST(Origin, OfATableReadFromAFileNamesItsFileAndLine) {
  const io::Node root = io::parse_config(schema(), "[dic]\n\nstep = 4\n", "dic.toml");
  const Origin o(root.section("dic"));
  const Location at = o.where("step");
  EXPECT_EQ(at.file, "dic.toml");
  EXPECT_EQ(at.line, 3);
  EXPECT_EQ(at.key, "dic.step");
}

TEST(Origin, OfAKeySetByAFlagNamesTheFlag) {
  const io::Node root = io::parse_config(schema(), "[dic]\nstep = 4\n", "dic.toml");
  Origin o(root.section("dic"));
  o.set_by_flag("step", "--step");
  EXPECT_EQ(message_of([&] { o.fail("step", "too coarse"); }), "command line: --step: too coarse");
}

TEST(Origin, PlacesAnEnginesErrorAtItsKeyWithoutRenamingIt) {
  const io::Node root = io::parse_config(schema(), "[dic]\nstep = 4\n", "dic.toml");
  const Origin o(root.section("dic"));
  const InputError engine(Location{"", 0, "dic.step"}, "out of range", "4", ">= 5 px");
  EXPECT_TRUE(o.owns(engine));
  EXPECT_FALSE(o.owns(InputError(Location{"", 0, "strain.window"}, "out of range")));
  EXPECT_FALSE(o.owns(InputError(Location{"dic.toml", 2, "dic.step"}, "already located")));
  EXPECT_EQ(message_of([&] { o.rethrow(engine); }), "dic.toml:2: dic.step: out of range (got 4, expected >= 5 px)");
}

TEST(ProblemOf, IsTheMessageAfterTheKey) {
  EXPECT_EQ(problem_of(InputError(Location{"", 0, "dic.step"}, "out of range", "4", "5")),
            "out of range (got 4, expected 5)");
}

}  // namespace
}  // namespace tricot::project
