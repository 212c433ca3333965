// project/lab_experiment.cpp: the [experiment] table of the lab file as a typed spec (the pipeline
// itself runs in tests/cli/experiment_test.cpp and experiment_slow_test.cpp).
#include "tricot/project/lab_experiment.hpp"

#include <gtest/gtest.h>

namespace tricot::project {
namespace {

std::string message_of(const ExperimentSpec& s) {
  try {
    s.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ExperimentSpec, TheSchemasDefaultsAreTheSpecsDefaults) {
  const ExperimentSpec read = ExperimentSpec::from_config(io::default_config(lab_schema()).section("experiment"));
  const ExperimentSpec code;
  EXPECT_EQ(read.field_kind, code.field_kind);
  EXPECT_EQ(read.control, code.control);
  EXPECT_EQ(read.grip, code.grip);
  EXPECT_EQ(read.plot, code.plot);
  EXPECT_EQ(read.sigma_edge_displacement, code.sigma_edge_displacement);
  EXPECT_EQ(read.project_template, code.project_template);
  EXPECT_EQ(message_of(code), "no error");
}

TEST(ExperimentSpec, ABadValueBuiltInCodeNamesItsKeyValueAndRange) {
  ExperimentSpec s;
  s.control = "forse";
  EXPECT_EQ(message_of(s),
            "experiment.control: not a valid choice; did you mean 'force'? (got \"forse\", expected one of "
            "displacement, force)");
  s = {};
  s.sigma_edge_displacement = -1;
  EXPECT_EQ(message_of(s), "experiment.sigma_edge_displacement: out of range (got -1.0, expected 0 to 1000000)");
}

TEST(ExperimentSpec, AFileIsReadWithItsTemplateBesideIt) {
  const io::Node root = io::parse_config(
      lab_schema(), "[experiment]\ncontrol = \"force\"\nproject_template = \"tpl.toml\"\n", "lab/lab.toml");
  const ExperimentSpec s = ExperimentSpec::from_config(root.section("experiment"));
  EXPECT_TRUE(s.force_control());
  EXPECT_EQ(s.project_template, std::filesystem::path("lab") / "tpl.toml");
  ExperimentSpec bad = s;
  bad.grip = "clamp";
  EXPECT_EQ(message_of(bad).rfind("lab/lab.toml:1: experiment.grip: not a valid choice", 0), 0u) << message_of(bad);
}

}  // namespace
}  // namespace tricot::project
