#include "tricot/ident/experiment.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/core/error.hpp"

namespace tricot::ident {
namespace {

TestData small_test() {
  TestData d;
  d.name = "uniaxial";
  d.source = "data/uniaxial.csv";
  d.loads = {1, 2, 3};
  d.edge_displacement = {0.5, 1.1, 1.8};
  d.point_ids = {7, 9};
  d.points.resize(2, 2);
  d.points << 1, 2, 3, 4;
  d.u = Eigen::MatrixXd::Zero(3, 2);
  d.v = Eigen::MatrixXd::Ones(3, 2);
  return d;
}

TEST(Experiment, AValidTestPasses) {
  Experiment e;
  e.tests = {small_test()};
  EXPECT_NO_THROW(e.validate());
  EXPECT_EQ(e.find("uniaxial"), &e.tests[0]);
  EXPECT_EQ(e.find("other"), nullptr);
}

TEST(Experiment, NanInTheFieldDataIsAnInputErrorNamingStepAndPoint) {
  TestData d = small_test();
  d.v(2, 1) = NAN;
  try {
    d.validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "experiment.uniaxial.v");
    EXPECT_EQ(e.where().file, "data/uniaxial.csv");
    EXPECT_NE(std::string(e.what()).find("step 2, point 9"), std::string::npos) << e.what();
  }
}

TEST(Experiment, NanInTheEdgeDataIsAnInputError) {
  TestData d = small_test();
  d.edge_displacement[1] = NAN;
  EXPECT_THROW(d.validate(), InputError);
}

TEST(Experiment, RejectsWrongSizesAndBadLoads) {
  TestData d = small_test();
  d.edge_force = {1, 2};
  EXPECT_THROW(d.validate(), InputError);
  d = small_test();
  d.u.resize(2, 2);
  EXPECT_THROW(d.validate(), InputError);
  d = small_test();
  d.loads = {1, NAN, 2};
  EXPECT_THROW(d.validate(), InputError);
  d = small_test();
  d.loads = {1, 1, 0.5};  // a lab record's hold and unloading (issue 29): the model's control decides
  EXPECT_NO_THROW(d.validate());
  d = small_test();
  d.point_ids = {7, 7};
  EXPECT_THROW(d.validate(), InputError);
  d = small_test();
  d.sigma.field = -1;
  EXPECT_THROW(d.validate(), InputError);
}

TEST(Experiment, RejectsDuplicateTestNames) {
  Experiment e;
  e.tests = {small_test(), small_test()};
  EXPECT_THROW(e.validate(), InputError);
}

}  // namespace
}  // namespace tricot::ident
