#include "tricot/io/config.hpp"

#include <gtest/gtest.h>

using namespace tricot;
using namespace tricot::io;

namespace {

SectionSpec schema() {
  SectionSpec root{"", "A test schema.", false, {}, {}};
  root.keys.push_back(key("name", std::string("strip"), "a name"));
  root.keys.push_back(key("width", 20.0, "full width in mm", 0.0, 1e4));
  root.keys.push_back({"steps", Reals{1.0, 2.0}, "grip displacements", 0.0, 1e3, {}, true});
  root.keys.push_back({"element", std::string("q8"), "element type", -1, 1, {"q4", "q8"}});
  SectionSpec mesh{"mesh", "The mesh.", false, {}, {}};
  mesh.keys.push_back(key("nx", std::int64_t{10}, "elements along x", 1, 1000));
  root.sections.push_back(mesh);
  SectionSpec test{"test", "One test.", true, {}, {}};
  test.keys.push_back(key("angle", 0.0, "material angle in degrees", -180, 180));
  root.sections.push_back(test);
  return root;
}

std::string error_of(std::string_view text) {
  try {
    parse_config(schema(), text, "case.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(Config, DefaultsFillEveryKeyThatIsNotGiven) {
  Node n = parse_config(schema(), "width = 30\n[mesh]\nnx = 4\n", "case.toml");
  EXPECT_DOUBLE_EQ(n.real("width"), 30.0);
  EXPECT_TRUE(n.given("width"));
  EXPECT_FALSE(n.given("name"));
  EXPECT_EQ(n.string("name"), "strip");
  EXPECT_EQ(n.section("mesh").integer("nx"), 4);
  EXPECT_TRUE(n.array("test").empty());
}

TEST(Config, ArraysOfTablesAreReadInOrder) {
  Node n = parse_config(schema(), "[[test]]\nangle = 0\n[[test]]\nangle = 90\n", "case.toml");
  ASSERT_EQ(n.array("test").size(), 2u);
  EXPECT_DOUBLE_EQ(n.array("test")[1].real("angle"), 90.0);
  EXPECT_EQ(n.array("test")[1].where("angle").key, "test[1].angle");
  EXPECT_EQ(n.array("test")[1].where("angle").line, 4);
}

TEST(Config, UnknownKeyNamesLineAndSuggestsTheClosestKey) {
  EXPECT_EQ(error_of("name = \"a\"\nwidht = 3\n"), "case.toml:2: widht: unknown key; did you mean 'width'?");
  EXPECT_EQ(error_of("[mesh]\nnz = 3\n"), "case.toml:2: mesh.nz: unknown key; did you mean 'nx'?");
}

TEST(Config, NegativeWidthIsOutOfRange) {
  EXPECT_EQ(error_of("width = -3\n"), "case.toml:1: width: out of range (got -3.0, expected 0 to 10000)");
}

TEST(Config, NanIsRejected) {
  EXPECT_EQ(error_of("width = nan\n"), "case.toml:1: width: must be a finite number (got nan, expected 0 to 10000)");
}

TEST(Config, StepsGoingBackwardsAreRejectedAtTheOffendingEntry) {
  EXPECT_EQ(error_of("steps = [1.0, 3.0, 2.0]\n"),
            "case.toml:1: steps[2]: must be larger than the value before it (got 2.0, expected > 3.0)");
}

TEST(Config, WrongTypeAndBadChoiceAreNamed) {
  EXPECT_EQ(error_of("width = \"wide\"\n"), "case.toml:1: width: must be a number (got \"wide\", expected 0 to 10000)");
  EXPECT_EQ(error_of("element = \"q9\"\n"),
            "case.toml:1: element: not a valid choice; did you mean 'q4'? (got \"q9\", expected one of q4, q8)");
  EXPECT_EQ(error_of("[mesh]\nnx = 2.5\n"), "case.toml:2: mesh.nx: must be an integer (got 2.5, expected 1 to 1000)");
}

TEST(Config, SyntaxErrorNamesTheLine) {
  EXPECT_EQ(error_of("width = 3\nname = \n").substr(0, 30), "case.toml:2: TOML syntax error");
}

TEST(Config, PrintedDefaultsReadBackToTheDefaults) {
  const std::string text = print_config(schema());
  EXPECT_NE(text.find("# full width in mm [0 to 10000]\nwidth = 20.0\n"), std::string::npos) << text;
  Node n = parse_config(schema(), text, "printed.toml");
  const Node d = default_config(schema());
  EXPECT_DOUBLE_EQ(n.real("width"), d.real("width"));
  EXPECT_EQ(n.reals("steps"), d.reals("steps"));
  EXPECT_EQ(n.section("mesh").integer("nx"), d.section("mesh").integer("nx"));
  ASSERT_EQ(n.array("test").size(), 1u);  // one example entry of each array is printed
}

TEST(Config, OverridesReplaceValuesAndCountAsGiven) {
  Node n = default_config(schema());
  n.set("width", 50.0);
  EXPECT_DOUBLE_EQ(n.real("width"), 50.0);
  EXPECT_TRUE(n.given("width"));
  EXPECT_THROW(n.set("width", std::string("x")), std::logic_error);
}

TEST(Config, MissingFileIsAFileError) { EXPECT_THROW(read_config(schema(), "/nonexistent/case.toml"), FileError); }

TEST(ClosestName, FindsTyposAndTranspositionsButNotStrangers) {
  EXPECT_EQ(closest_name("widht", {"width", "height"}), "width");
  EXPECT_EQ(closest_name("hieght", {"width", "height"}), "height");
  EXPECT_EQ(closest_name("zzzzzz", {"width", "height"}), "");
}

TEST(Config, AWordKeyThatAlsoTakesANumberKeepsTheNumber) {
  SectionSpec s{"", "A word-or-number key.", false, {}, {}};
  s.keys.push_back(key("side", std::string("free"), "free, guide or a size in mm", -1e9, 1e9, {"free", "guide"}));
  s.keys.back().or_number = true;
  const Node n = parse_config(s, "side = 110\n", "case.toml");
  EXPECT_EQ(std::get<double>(n.value("side")), 110.0);
  EXPECT_EQ(parse_config(s, "side = \"guide\"\n", "case.toml").string("side"), "guide");
  try {
    parse_config(s, "side = \"gide\"\n", "case.toml");
    FAIL() << "a word outside the choices was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "side");
    EXPECT_EQ(e.where().line, 1);
  }
}
