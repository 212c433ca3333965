// tricot demo (apps/tricot/demo.cpp, src/project/demo.cpp): its built-in files are the examples a user runs by hand.
#include "tricot/project/demo.hpp"

#include <gtest/gtest.h>

#include "tricot/project/identification.hpp"
#include "tricot/project/synthesis.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

const std::filesystem::path kExample = test::source_dir() / "examples" / "uniaxial-mooney";

TEST(Demo, ExampleExperimentIsTheDemosExperiment) {
  EXPECT_EQ(io::read_text(kExample / "experiment.toml"), demo_experiment_toml())
      << "regenerate: tricot demo --print-example experiment > examples/uniaxial-mooney/experiment.toml";
}

TEST(Demo, ExampleProjectIsTheDemosBothDataProject) {
  EXPECT_EQ(io::read_text(kExample / "project.toml"), demo_project_toml({}))
      << "regenerate: tricot demo --print-example project > examples/uniaxial-mooney/project.toml";
}

TEST(Demo, ItsFilesAreValidForTheirVerbs) {
  const io::Node e = io::parse_config(synth_schema(), demo_experiment_toml(0.005), "experiment.toml");
  EXPECT_EQ(e.section("synth").real("noise_relative"), 0.005);
  EXPECT_EQ(e.array("test").front().string("control"), "force");
  DemoProject p;
  p.field = 0;
  p.jacobian = "finite_difference";
  p.epsilon = 1e-4;
  const io::Node r = io::parse_config(identify_schema(), demo_project_toml(p), "project.toml");
  EXPECT_EQ(r.section("data").real("field"), 0.0);
  EXPECT_EQ(r.section("identify").string("jacobian"), "finite_difference");
  EXPECT_EQ(r.section("identify").real("epsilon"), 1e-4);
  EXPECT_EQ(r.array("parameter").size(), 4u);
}

}  // namespace
}  // namespace tricot::project
