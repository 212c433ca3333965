// The experiment on disk (src/project/output/experiment_files.cpp): what synth writes, identify reads.
#include "tricot/project/experiment_files.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/core/error.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;
using test::scratch_dir;
using test::write_file;

ident::TestData two_steps_two_points() {
  ident::TestData d;
  d.name = "t";
  d.loads = {0.5, 1.0 / 3.0 + 1};
  d.edge_displacement = {0.1, 0.2000000000000001};
  d.edge_force = {0.5, 1.3333333333333333};
  d.point_ids = {7, 3};
  d.points.resize(2, 2);
  d.points << 1.25, 2.5, 3.0 / 7.0, 10;
  d.u.resize(2, 2);
  d.v.resize(2, 2);
  d.u << -0.01, 1e-17, -0.02, 2e-3;
  d.v << 0.1, 0.2, 0.3, 0.4;
  return d;
}

// A test's folder with forces.csv for two steps and the given field.csv text.
fs::path folder_with_field(const std::string& name, const std::string& field) {
  const fs::path dir = scratch_dir(name);
  write_file(dir / "t" / kForcesFile, "step,load,edge_displacement\n1,1.0,0.5\n2,2.0,1.0\n");
  write_file(dir / "t" / kFieldFile, field);
  return dir;
}

std::string error_of(const fs::path& dir) {
  try {
    read_test_data(dir, "t", ident::FieldKind::cumulative);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ExperimentFiles, WhatIsWrittenReadsBackBitForBit) {
  const fs::path dir = scratch_dir("experiment_files_round_trip");
  const ident::TestData d = two_steps_two_points();
  write_test_data(dir, d);
  const ident::TestData r = read_test_data(dir, "t", ident::FieldKind::incremental);
  EXPECT_EQ(r.name, "t");
  EXPECT_EQ(r.field_kind, ident::FieldKind::incremental);
  EXPECT_EQ(r.loads, d.loads);
  EXPECT_EQ(r.edge_displacement, d.edge_displacement);
  EXPECT_EQ(r.edge_force, d.edge_force);
  EXPECT_EQ(r.point_ids, d.point_ids);
  EXPECT_EQ(r.points, d.points);
  EXPECT_EQ(r.u, d.u);
  EXPECT_EQ(r.v, d.v);
  EXPECT_NO_THROW(r.validate());
}

TEST(ExperimentFiles, EdgeDataWithoutAColumnIsNotMeasured) {
  const fs::path dir = scratch_dir("experiment_files_no_force");
  write_file(dir / "t" / kForcesFile, "step,load,edge_displacement\n1,1.0,0.5\n2,2.0,1.0\n");
  const ident::TestData r = read_test_data(dir, "t", ident::FieldKind::cumulative);
  EXPECT_EQ(r.edge_displacement, (std::vector<double>{0.5, 1.0}));
  EXPECT_TRUE(r.edge_force.empty());
  EXPECT_FALSE(r.has_field());
}

TEST(ExperimentFiles, FieldRowsMayComeInAnyOrder) {
  const fs::path dir =
      folder_with_field("experiment_files_order",
                        "step,id,x,y,u,v\n2,5,1,2,0.3,0.4\n1,9,3,4,0.5,0.6\n1,5,1,2,0.1,0.2\n2,9,3,4,0.7,0.8\n");
  const ident::TestData r = read_test_data(dir, "t", ident::FieldKind::cumulative);
  ASSERT_EQ(r.point_ids, (std::vector<int>{5, 9}));
  EXPECT_EQ(r.u(0, 0), 0.1);
  EXPECT_EQ(r.u(1, 0), 0.3);
  EXPECT_EQ(r.v(0, 1), 0.6);
  EXPECT_EQ(r.v(1, 1), 0.8);
}

TEST(ExperimentFiles, ReadsThePerPointSigmaOfTricotExperiment) {
  const fs::path dir = folder_with_field("experiment_files_sigma",
                                         "step,id,x,y,u,v,sigma_u,sigma_v\n1,5,1,2,0.1,0.2,0.001,0.002\n"
                                         "2,5,1,2,0.3,0.4,0.003,0.004\n");
  const ident::TestData r = read_test_data(dir, "t", ident::FieldKind::cumulative);
  ASSERT_EQ(r.sigma_u.rows(), 2);
  EXPECT_EQ(r.sigma_u(0, 0), 0.001);
  EXPECT_EQ(r.sigma_v(1, 0), 0.004);
  EXPECT_NO_THROW(r.validate());
}

TEST(ExperimentFiles, AFieldWithoutSigmaColumnsHasNoPerPointSigma) {
  const fs::path dir =
      folder_with_field("experiment_files_no_sigma", "step,id,x,y,u,v\n1,5,1,2,0.1,0.2\n2,5,1,2,0.3,0.4\n");
  EXPECT_EQ(read_test_data(dir, "t", ident::FieldKind::cumulative).sigma_u.size(), 0);
}

TEST(ExperimentFiles, NanInTheFieldNamesFileLineAndColumn) {
  const fs::path dir = folder_with_field("experiment_files_nan", "step,id,x,y,u,v\n1,1,1,2,0.1,0.2\n2,1,1,2,nan,0.4\n");
  EXPECT_NE(error_of(dir).find("field.csv:3: u: not a finite number"), std::string::npos) << error_of(dir);
}

TEST(ExperimentFiles, ARepeatedPointAtOneStepNamesBothLines) {
  const fs::path dir = folder_with_field("experiment_files_repeat",
                                         "step,id,x,y,u,v\n1,1,1,2,0.1,0.2\n2,1,1,2,0.3,0.4\n2,1,1,2,0.3,0.4\n");
  const std::string e = error_of(dir);
  EXPECT_NE(e.find("field.csv:4: id: point 1 appears twice at step 2 (also line 3)"), std::string::npos) << e;
}

TEST(ExperimentFiles, APointThatMovesBetweenStepsIsAnError) {
  const fs::path dir =
      folder_with_field("experiment_files_moves", "step,id,x,y,u,v\n1,1,1,2,0.1,0.2\n2,1,1.5,2,0.3,0.4\n");
  const std::string e = error_of(dir);
  EXPECT_NE(e.find("field.csv:3: x: point 1 moved"), std::string::npos) << e;
}

TEST(ExperimentFiles, APointMissingAtAStepIsNamed) {
  const fs::path dir = folder_with_field("experiment_files_missing",
                                         "step,id,x,y,u,v\n1,1,1,2,0.1,0.2\n1,2,3,2,0.1,0.2\n2,1,1,2,0.3,0.4\n");
  EXPECT_NE(error_of(dir).find("point 2 has no row for step 2"), std::string::npos) << error_of(dir);
}

TEST(ExperimentFiles, AFieldStepBeyondTheForcesIsNamed) {
  const fs::path dir =
      folder_with_field("experiment_files_step", "step,id,x,y,u,v\n1,1,1,2,0.1,0.2\n3,1,1,2,0.3,0.4\n");
  EXPECT_NE(error_of(dir).find("field.csv:3: step: step out of range"), std::string::npos) << error_of(dir);
}

TEST(ExperimentFiles, StepsOutOfOrderInForcesAreNamed) {
  const fs::path dir = scratch_dir("experiment_files_forces_order");
  write_file(dir / "t" / kForcesFile, "step,load\n1,1.0\n3,2.0\n");
  EXPECT_NE(error_of(dir).find("forces.csv:3: step: steps must be numbered"), std::string::npos) << error_of(dir);
}

TEST(ExperimentFiles, AMissingFolderIsAFileError) {
  const fs::path dir = scratch_dir("experiment_files_missing_folder");
  EXPECT_THROW(read_experiment(dir / "nowhere", {"t"}, ident::FieldKind::cumulative), FileError);
  EXPECT_THROW(read_experiment(dir, {"t"}, ident::FieldKind::cumulative), FileError);  // no t/
}

// The JSON fuzzer's crash (issue 14): a number too large for a double is nlohmann's out_of_range,
// not a parse_error; it was thrown past the reader and ended the process.
TEST(ExperimentFiles, ATruthWhoseNumberOverflowsIsAnInputErrorNamingTheFile) {
  const fs::path dir = scratch_dir("experiment_files_truth_overflow");
  std::ofstream(dir / kTruthFile) << "8484E4444484444";
  try {
    (void)read_truth(dir);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / kTruthFile).string() + ": not valid JSON"), std::string::npos)
        << e.what();
  }
}

TEST(ExperimentFiles, TruthReadsBackAsWritten) {
  const fs::path dir = scratch_dir("experiment_files_truth");
  EXPECT_FALSE(read_truth(dir).has_value());
  Truth t;
  t.law = "mooney_rivlin";
  t.names = {"C10", "C03"};
  t.values = {0.1, 0.01};
  t.noise_relative = 0.005;
  t.seed = 42;
  t.field_kind = ident::FieldKind::incremental;
  Truth::Test s;
  s.name = "tension";
  s.control = "force";
  s.mesh.nx = 14;
  s.mesh.width = 25;
  s.dofs = 4282;
  s.steps = 35;
  s.points = 120;
  s.sigma = {0.01, 0.02, 0.003};
  t.tests.push_back(s);
  write_truth(dir, t);
  const auto r = read_truth(dir);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->names, t.names);
  EXPECT_EQ(r->values, t.values);
  EXPECT_EQ(r->value("C03"), 0.01);
  EXPECT_FALSE(r->value("C20").has_value());
  EXPECT_EQ(r->seed, 42u);
  EXPECT_EQ(r->field_kind, ident::FieldKind::incremental);
  ASSERT_NE(r->find("tension"), nullptr);
  EXPECT_EQ(r->find("tension")->mesh.width, 25);
  EXPECT_EQ(r->find("tension")->mesh.nx, 14);
  EXPECT_EQ(r->find("tension")->sigma.field, 0.003);
}

}  // namespace
}  // namespace tricot::project
