// tricot demo (apps/tricot/demo.cpp, src/project/pipeline/demo.cpp, campaign_demo.cpp): its files are
// the examples a user runs by hand, built into tricot (project/examples.hpp).
#include "tricot/project/demo.hpp"

#include <gtest/gtest.h>

#include "tricot/fem/mooney_rivlin.hpp"
#include "tricot/project/campaign_demo.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/examples.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/lab_experiment.hpp"
#include "tricot/project/synthesis.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

const std::filesystem::path kExamples = test::source_dir() / "examples";
const std::filesystem::path kExample = kExamples / "uniaxial-mooney";

TEST(Demo, ExampleExperimentIsTheDemosExperiment) {
  EXPECT_EQ(io::read_text(kExample / "experiment.toml"), demo_experiment_toml()) << "rebuild tricot";
}

TEST(Demo, ExampleProjectIsTheDemosBothDataProject) {
  EXPECT_EQ(io::read_text(kExample / "project.toml"), demo_project_toml({})) << "rebuild tricot";
}

TEST(Demo, EveryBuiltInFileIsTheExampleFileByteForByte) {
  ASSERT_GE(example_files().size(), 10u);
  for (const ExampleFile& f : example_files()) EXPECT_EQ(io::read_text(kExamples / f.path), f.text) << f.path;
  EXPECT_EQ(example_file("uniaxial-mooney/project.toml"), io::read_text(kExample / "project.toml"));
  EXPECT_THROW(example_file("uniaxial-mooney/nope.toml"), std::logic_error);
}

// Table 1's targets are the experiment's law: the paper's coefficients.
TEST(Demo, ItsExperimentsLawIsThePapersTruth) {
  const io::Node e = io::parse_config(synth_schema(), demo_experiment_toml(), "experiment.toml");
  const io::Node& law = e.section("law").section("mooney_rivlin");
  const auto terms = fem::paper_mooney_rivlin_terms();
  ASSERT_EQ(law.reals("values").size(), terms.size());
  for (std::size_t k = 0; k < terms.size(); ++k) {
    EXPECT_EQ(law.strings("terms")[k], "C" + std::to_string(terms[k].i) + std::to_string(terms[k].j));
    EXPECT_EQ(law.reals("values")[k], terms[k].C);
  }
}

// A variant is the example with one value changed, its comment kept, every other byte the same.
TEST(Demo, AVariantChangesOneValueOfItsTableAndKeepsTheComment) {
  const std::string toml =
      "top = 1\n[a]\nfield_kind = \"x\"  # not field\nfield = 1.0   # weight\n[a.b]\nfield = 2.0\n"
      "[[t]]\nname = \"a # b\" # c\n";
  EXPECT_EQ(with_value(toml, "a", "field", 0.0),
            "top = 1\n[a]\nfield_kind = \"x\"  # not field\nfield = 0.0   # weight\n[a.b]\nfield = 2.0\n"
            "[[t]]\nname = \"a # b\" # c\n");
  EXPECT_EQ(with_value(toml, "a.b", "field", io::Reals{1, 2}),
            "top = 1\n[a]\nfield_kind = \"x\"  # not field\nfield = 1.0   # weight\n[a.b]\nfield = [1.0, 2.0]\n"
            "[[t]]\nname = \"a # b\" # c\n");
  EXPECT_EQ(with_value(toml, "t", "name", std::string("z")),
            "top = 1\n[a]\nfield_kind = \"x\"  # not field\nfield = 1.0   # weight\n[a.b]\nfield = 2.0\n"
            "[[t]]\nname = \"z\" # c\n");
  EXPECT_EQ(with_value(toml, "", "top", std::int64_t{2}).substr(0, 8), "top = 2\n");
  EXPECT_THROW(with_value(toml, "a", "top", 0.0), std::logic_error);
  EXPECT_THROW(with_value(toml, "b", "field", 0.0), std::logic_error);
}

// The campaign's files (examples/knit-campaign/demo and its small/) are valid for their verbs, and
// the reduced chain is the one its doc says: two tests, 6 pull steps, 320 × 256 px.
TEST(Demo, TheCampaignsFilesAreValidForTheirVerbs) {
  for (const bool small : {false, true}) {
    SCOPED_TRACE(small);
    const std::string dir = campaign_example({small});
    const io::Node e = io::parse_config(synth_schema(), example_file(dir + "/experiment.toml"), "experiment.toml");
    const io::Node l = io::parse_config(lab_schema(), example_file(dir + "/lab.toml"), "lab.toml");
    const io::Node d = io::parse_config(dic_schema(), example_file(dir + "/dic.toml"), "dic.toml");
    EXPECT_EQ(d.section("dic").string("mode"), "incremental");
    ASSERT_EQ(e.array("test").size(), small ? 2u : 10u);
    ASSERT_EQ(l.array("test").size(), e.array("test").size());
    for (std::size_t k = 0; k < e.array("test").size(); ++k) {
      EXPECT_EQ(l.array("test")[k].string("name"), e.array("test")[k].string("name"));
      EXPECT_EQ(e.array("test")[k].integer("steps"), small ? 6 : 21);
    }
    EXPECT_EQ(e.section("synth").section("images").integer("width"), small ? 320 : 1280);
    EXPECT_EQ(l.section("experiment").string("project_template"), "project-template.toml");
  }
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

// What demo runs (the spec built in code) is what its project.toml says: the file read back gives
// the same values, defaults included, for every key the identification reads.
TEST(Demo, ItsProjectFileReadsBackAsTheSpecItRuns) {
  DemoProject p;
  p.start = {0.1, -0.02, 0.003, 0.004};
  p.field = 0;
  p.sigma_from_truth = true;
  const IdentificationSpec code = demo_project_spec(p);
  const IdentificationSpec file =
      read_identification_spec(io::parse_config(identify_schema(), demo_project_toml(p), "project.toml"));
  EXPECT_EQ(code.mesh.width, file.mesh.width);
  EXPECT_EQ(code.mesh.height, file.mesh.height);
  EXPECT_EQ(code.mesh.type, file.mesh.type);
  EXPECT_EQ(code.mesh.nx, file.mesh.nx);
  EXPECT_EQ(code.mesh.ny, file.mesh.ny);
  EXPECT_EQ(code.mesh.grading, file.mesh.grading);
  EXPECT_EQ(code.mesh.grading_x, file.mesh.grading_x);
  EXPECT_EQ(code.law.type, file.law.type);
  EXPECT_EQ(code.law.mooney_rivlin.terms, file.law.mooney_rivlin.terms);
  EXPECT_EQ(code.law.mooney_rivlin.values, file.law.mooney_rivlin.values);
  EXPECT_EQ(code.solver.tolerance, file.solver.tolerance);
  EXPECT_EQ(code.solver.max_iterations, file.solver.max_iterations);
  EXPECT_EQ(code.solver.line_search, file.solver.line_search);
  EXPECT_EQ(code.solver.max_cutbacks, file.solver.max_cutbacks);
  ASSERT_EQ(code.test.size(), file.test.size());
  const TestSpec &a = code.test.front(), &b = file.test.front();
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.material_angle, b.material_angle);
  EXPECT_EQ(a.control, b.control);
  EXPECT_EQ(a.grip_holds_x, b.grip_holds_x);
  EXPECT_EQ(a.grip_follows_guide, b.grip_follows_guide);
  EXPECT_EQ(a.side, b.side);
  EXPECT_EQ(a.guide, b.guide);
  EXPECT_EQ(a.loads, b.loads);
  EXPECT_EQ(a.load_max, b.load_max);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.mesh.nx, b.mesh.nx);
  EXPECT_EQ(a.mesh.width, b.mesh.width);
  EXPECT_EQ(code.experiment.dir, file.experiment.dir);
  EXPECT_EQ(code.experiment.field_kind, file.experiment.field_kind);
  EXPECT_EQ(code.experiment.sigma_from_truth, file.experiment.sigma_from_truth);
  EXPECT_EQ(code.experiment.sigma_field, file.experiment.sigma_field);
  ASSERT_EQ(code.parameter.size(), file.parameter.size());
  for (std::size_t k = 0; k < code.parameter.size(); ++k) {
    EXPECT_EQ(code.parameter[k].name, file.parameter[k].name);
    EXPECT_EQ(code.parameter[k].start, file.parameter[k].start);
    EXPECT_EQ(code.parameter[k].scale, file.parameter[k].scale);
    EXPECT_EQ(code.parameter[k].bounds, file.parameter[k].bounds);
  }
  EXPECT_EQ(code.data.edge_displacement, file.data.edge_displacement);
  EXPECT_EQ(code.data.edge_force, file.data.edge_force);
  EXPECT_EQ(code.data.field, file.data.field);
  EXPECT_EQ(code.data.field_uv, file.data.field_uv);
  EXPECT_EQ(code.data.field_sigma, file.data.field_sigma);
  const ident::IdentifyOptions oc = code.identify.options(), of = file.identify.options();
  EXPECT_EQ(oc.epsilon, of.epsilon);
  EXPECT_EQ(oc.delta, of.delta);
  EXPECT_EQ(oc.function_tolerance, of.function_tolerance);
  EXPECT_EQ(oc.gradient_tolerance, of.gradient_tolerance);
  EXPECT_EQ(oc.max_iterations, of.max_iterations);
  EXPECT_EQ(oc.stability_test, of.stability_test);
  EXPECT_EQ(oc.stability_eta, of.stability_eta);
  EXPECT_EQ(oc.max_restarts, of.max_restarts);
  EXPECT_EQ(oc.jacobian, of.jacobian);
  EXPECT_EQ(oc.difference, of.difference);
  EXPECT_EQ(oc.fd_step, of.fd_step);
  EXPECT_EQ(oc.threads, of.threads);
  EXPECT_EQ(oc.initial_trust_region_radius, of.initial_trust_region_radius);
  EXPECT_EQ(code.eq9.practical_course, file.eq9.practical_course);
  EXPECT_EQ(code.eq9.practical_wale, file.eq9.practical_wale);
  EXPECT_EQ(code.eq9.nearest, file.eq9.nearest);
}

}  // namespace
}  // namespace tricot::project
