// project/identification_spec.cpp: the [identify] table, its defaults and the engine options it builds,
// each error once, at its key; the project's spec read from a file or built in code, and its one check.
#include <gtest/gtest.h>

#include "tricot/project/identification.hpp"

namespace tricot::project {
namespace {

std::string message_of(const IdentifyTable& t) {
  try {
    t.options();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(IdentifyTable, TheSchemasDefaultsAreTheEnginesDefaults) {
  const io::Node root = io::default_config(identify_schema());
  const ident::IdentifyOptions read = IdentifyTable::from_config(root.section("identify")).options();
  const ident::IdentifyOptions engine;
  EXPECT_EQ(read.epsilon, engine.epsilon);
  EXPECT_EQ(read.delta, engine.delta);
  EXPECT_EQ(read.max_iterations, engine.max_iterations);
  EXPECT_EQ(read.fd_step, engine.fd_step);
  EXPECT_EQ(read.jacobian, engine.jacobian);
  EXPECT_EQ(read.initial_trust_region_radius, engine.initial_trust_region_radius);
  EXPECT_EQ(read.line_search_trials, engine.line_search_trials);
  EXPECT_EQ(IdentifyTable::from_config(root.section("identify")).objective.warm_start,
            ident::ObjectiveOptions{}.warm_start);
  const io::Node warm = io::parse_config(identify_schema(), "[identify]\nwarm_start = true\n", "project.toml");
  EXPECT_TRUE(IdentifyTable::from_config(warm.section("identify")).objective.warm_start);
}

TEST(IdentifyTable, AnEnginesErrorNamesTheConfigKey) {
  IdentifyTable t;
  t.lm.fd_step = 0.5;
  EXPECT_EQ(message_of(t), "identify.fd_step: out of range (got 0.5, expected (0, 0.1])");
}

TEST(IdentifyTable, AnErrorOfAFileNamesItsLine) {
  const io::Node root = io::parse_config(identify_schema(), "[identify]\ndelta = 0.0\n", "project.toml");
  EXPECT_EQ(message_of(IdentifyTable::from_config(root.section("identify"))),
            "project.toml:2: identify.delta: out of range (got 0, expected (0, 1))");
}

// A project built in code: one default uniaxial test, C10 of the default Mooney–Rivlin law identified.
IdentificationSpec small_project() {
  IdentificationSpec s;
  s.test.emplace_back();
  s.parameter.emplace_back();
  return s;
}

std::string message_of(const IdentificationSpec& s) {
  try {
    s.validate();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(IdentificationSpec, ASmallProjectBuiltInCodeIsValid) { EXPECT_EQ(message_of(small_project()), "no error"); }

TEST(IdentificationSpec, ABadValueBuiltInCodeIsNamedByItsDottedKey) {
  IdentificationSpec s = small_project();
  s.parameter.front().name = "C99";
  EXPECT_EQ(message_of(s).rfind("parameter.name: not a coefficient of the mooney_rivlin law in [law]", 0), 0u)
      << message_of(s);
  s = small_project();
  s.experiment.field_kind = "total";
  EXPECT_EQ(message_of(s),
            "experiment.field_kind: not a valid choice (got \"total\", expected one of cumulative, incremental)");
  s = small_project();
  s.data.field_sigma = "each";
  EXPECT_EQ(message_of(s), "data.field_sigma: not a valid choice (got \"each\", expected one of group, per_point)");
  s = small_project();
  s.eq9.practical_wale = io::Reals{0.4, 0.2};
  EXPECT_EQ(message_of(s),
            "eq9.practical_wale: not a strain interval (got 2 values, expected [min, max] with min <= max)");
  s = small_project();
  s.identify.lm.delta = 1;
  EXPECT_EQ(message_of(s), "identify.delta: out of range (got 1, expected (0, 1))");
}

TEST(IdentificationSpec, TheEnginesCheckTheirDeclaredRangesAndAFileNamesTheLine) {
  IdentificationSpec s = small_project();
  s.identify.lm.max_iterations = 0;
  EXPECT_EQ(message_of(s), "identify.max_iterations: out of range (got 0, expected 1 to 100000)");
  s = small_project();
  s.identifiability.pinned_relative_error = 2e6;
  EXPECT_EQ(message_of(s),
            "identifiability.pinned_relative_error: out of range (got 2000000.0, expected 0 to 1000000)");
  const std::string head = "[[test]]\nname = \"t\"\n[[parameter]]\nname = \"C10\"\n";
  const io::Node zero =
      io::parse_config(identify_schema(), head + "[identifiability]\npinned_relative_error = 0.0\n", "project.toml");
  EXPECT_EQ(message_of(read_identification_spec(zero)),
            "project.toml:6: identifiability.pinned_relative_error: out of range (got 0, expected > 0)");
  const io::Node barrier = io::parse_config(
      identify_schema(), head + "[stability]\nenabled = true\nweight = 1.0\ntaut_stress = 0.0\n", "project.toml");
  ASSERT_TRUE(read_identification_spec(barrier).stability.has_value());
  EXPECT_EQ(read_identification_spec(barrier).stability->weight, 1.0);
  EXPECT_EQ(message_of(read_identification_spec(barrier)),
            "project.toml:8: stability.taut_stress: out of range (got 0, expected > 0)");
}

TEST(IdentificationSpec, ProjectsThatIdentifyNothingOrTwiceAreRejected) {
  IdentificationSpec s = small_project();
  s.parameter.clear();
  EXPECT_EQ(
      message_of(s),
      "parameter: the project identifies nothing (got no [[parameter]], expected one [[parameter]] per coefficient)");
  s = small_project();
  s.parameter.push_back(s.parameter.front());
  EXPECT_EQ(message_of(s), "parameter.name: this coefficient is identified twice (got \"C10\", expected unique names)");
}

TEST(IdentificationSpec, AFileIsReadIntoTheSpecWithItsLines) {
  const io::Node root = io::parse_config(identify_schema(),
                                         "[[test]]\nname = \"t\"\n[[parameter]]\nname = \"C20\"\nstart = 0.5\n"
                                         "[experiment]\ndir = \"data\"\n[eq9]\nnearest = 4\n",
                                         "project.toml");
  const IdentificationSpec s = read_identification_spec(root);
  ASSERT_EQ(s.test.size(), 1u);
  EXPECT_EQ(s.test.front().name, "t");
  ASSERT_EQ(s.parameter.size(), 1u);
  EXPECT_EQ(s.parameter.front().name, "C20");
  EXPECT_EQ(s.parameter.front().start, 0.5);
  EXPECT_EQ(s.experiment.dir, "data");
  EXPECT_EQ(s.eq9.nearest, 4);
  EXPECT_FALSE(s.eq9.practical_course.has_value());
  EXPECT_EQ(s.file, "project.toml");
  IdentificationSpec bad = s;
  bad.parameter.front().name = "C22";
  EXPECT_EQ(message_of(bad).rfind("project.toml:4: parameter[0].name: not a coefficient", 0), 0u) << message_of(bad);
}

}  // namespace
}  // namespace tricot::project
