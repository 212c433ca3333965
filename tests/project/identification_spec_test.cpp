// project/identification_spec.cpp: the [identify] table, its defaults and the engine options it builds,
// each error once, at its key.
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
}

TEST(IdentifyTable, AnEnginesErrorNamesTheConfigKey) {
  IdentifyTable t;
  t.fd_step = 0.5;
  EXPECT_EQ(message_of(t), "identify.fd_step: out of range (got 0.5, expected (0, 0.1])");
}

TEST(IdentifyTable, AnErrorOfAFileNamesItsLine) {
  const io::Node root = io::parse_config(identify_schema(), "[identify]\ndelta = 0.0\n", "project.toml");
  EXPECT_EQ(message_of(IdentifyTable::from_config(root.section("identify"))),
            "project.toml:2: identify.delta: out of range (got 0, expected (0, 1))");
}

}  // namespace
}  // namespace tricot::project
