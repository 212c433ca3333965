#include "tricot/fem/model.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "tricot/core/error.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/solver.hpp"

namespace tricot::fem {
namespace {

TestModel good() {
  MeshOptions m;
  m.nx = 2, m.ny = 2, m.type = ElementType::Q4;
  TestModel t;
  t.name = "uni";
  t.mesh = make_quarter_mesh(m);
  t.loads = {1, 2, 3};
  return t;
}

// The key of the InputError that validate() throws, "" when it passes; the message must name the test.
std::string key_of(const TestModel& t) {
  try {
    t.validate();
  } catch (const InputError& e) {
    if (!t.name.empty()) {
      EXPECT_NE(std::string(e.what()).find("'" + t.name + "'"), std::string::npos) << e.what();
    }
    return e.where().key;
  }
  return "";
}

TEST(TestModel, AConsistentModelIsValid) {
  EXPECT_EQ(key_of(good()), "");
  TestModel t = good();
  t.side = SideEdge::guide;
  t.guide = {-1};
  EXPECT_EQ(key_of(t), "");
  t.guide = {-1, -2, -3};
  EXPECT_EQ(key_of(t), "");
}

// Under force control only (issue 29: a displacement-controlled grip may hold and go back).
TEST(TestModel, ForceStepsThatGoBackwardsOrStartAtZeroAreRejected) {
  TestModel t = good();
  t.control = GripControl::force;
  t.loads = {1, 3, 2};
  EXPECT_EQ(key_of(t), "test.loads");
  try {
    t.validate();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("step 3"), std::string::npos) << e.what();
  }
  t.loads = {0, 1};
  EXPECT_EQ(key_of(t), "test.loads");
  t.loads = {1, 1};
  EXPECT_EQ(key_of(t), "test.loads");
  t.loads = {};
  EXPECT_EQ(key_of(t), "test.loads");
  t.loads = {1, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_EQ(key_of(t), "test.loads");
}

// A lab record's grip path (issue 29): a hold, an unloading, a reload. The law is elastic, so the state
// depends on the grip alone: the force at a grip visited twice is the same, to Newton's tolerance.
TEST(TestModel, ADisplacementPathWithHoldsAndUnloadingSolvesAndAnElasticLawRetracesIt) {
  TestModel t = good();
  t.loads = {0.5, 1.0, 1.0, 0.5, 0.0, 1.0, 1.5};
  EXPECT_EQ(key_of(t), "");
  const SimulationResult r = simulate(t, NeoHookean(1.0, 2.0));
  ASSERT_TRUE(r.usable()) << r.message;
  ASSERT_EQ(r.steps.size(), 7u);
  constexpr double kNewton = 1e-6;  // relative: the solver's default tolerance, with a margin
  const double F1 = r.steps[1].edge_force;
  EXPECT_GT(F1, 0);
  EXPECT_NEAR(r.steps[2].edge_force, F1, kNewton * F1);                     // the hold
  EXPECT_NEAR(r.steps[3].edge_force, r.steps[0].edge_force, kNewton * F1);  // back to 0.5
  EXPECT_NEAR(r.steps[4].edge_force, 0.0, kNewton * F1);                    // unloaded
  EXPECT_NEAR(r.steps[5].edge_force, F1, kNewton * F1);                     // reloaded to 1.0
}

TEST(TestModel, GuideValuesMustMatchTheSideEdge) {
  TestModel t = good();
  t.side = SideEdge::guide;
  EXPECT_EQ(key_of(t), "test.guide");  // none given
  t.guide = {1, 2};
  EXPECT_EQ(key_of(t), "test.guide");  // neither 1 nor one per step
  t.guide = {std::numeric_limits<double>::infinity()};
  EXPECT_EQ(key_of(t), "test.guide");
  t = good();
  t.guide = {-1};
  EXPECT_EQ(key_of(t), "test.guide");  // given for a free side
}

TEST(TestModel, ABrokenMeshIsRejected) {
  TestModel t = good();
  t.mesh = Mesh{};
  EXPECT_EQ(key_of(t), "test.mesh");
  t = good();
  t.mesh.connectivity[0][2] = 99;
  EXPECT_EQ(key_of(t), "test.mesh");
  t = good();
  t.mesh.top.clear();
  EXPECT_EQ(key_of(t), "test.mesh");
  t = good();
  std::swap(t.mesh.connectivity[0][1], t.mesh.connectivity[0][3]);  // clockwise: inverted
  EXPECT_EQ(key_of(t), "test.mesh");
  t = good();
  t.mesh.X(0, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(key_of(t), "test.mesh");
}

TEST(TestModel, ANonFiniteAngleOrAnEmptyNameIsRejected) {
  TestModel t = good();
  t.material_angle = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(key_of(t), "test.material_angle");
  t = good();
  t.name = "";
  EXPECT_EQ(key_of(t), "test.name");
}

}  // namespace
}  // namespace tricot::fem
