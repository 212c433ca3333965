// fem/assembly.cpp: the dof map and the global internal forces (docs/theory.md §4, §6). White-box: the
// engine's private header. The tangent against finite differences is checked in solver_test.cpp
// (GlobalTangent), through the same Assembler.
#include "assembly.hpp"

#include <gtest/gtest.h>

#include <omp.h>

#include <random>

#include "tricot/fem/mesh.hpp"
#include "tricot/fem/neo_hookean.hpp"
#include "tricot/fem/response_surface.hpp"

namespace tricot::fem::detail {
namespace {

constexpr double kRoundOff = 1e-12;  // sums of element forces of order 1 N

TestModel clamped_strip(ElementType type) {
  MeshOptions o;
  o.width = 10, o.height = 20, o.nx = 3, o.ny = 4, o.type = type;
  TestModel t;
  t.mesh = make_quarter_mesh(o);
  t.loads = {1};
  return t;
}

TEST(DofMap, PrescribesTheSymmetryEdgesAndTheClampedGrip) {
  const TestModel t = clamped_strip(ElementType::Q8);
  const DofMap d = make_dof_map(t);
  int prescribed = 0;
  for (int e : d.eq) prescribed += e < 0;
  // u_x = 0 on x = 0 and u_y = 0 on y = 0; the clamp holds u_x and u_y of the top edge.
  const int expected = int(t.mesh.left.size()) + int(t.mesh.bottom.size()) + 2 * int(t.mesh.top.size()) - 1;
  EXPECT_EQ(prescribed, expected);  // the top-left corner's u_x is both on the axis and in the clamp
  EXPECT_EQ(d.equations, t.mesh.dofs() - prescribed);
  EXPECT_EQ(d.master, -1);  // displacement control
  EXPECT_EQ(d.top_y.size(), t.mesh.top.size());
}

TEST(DofMap, ForceControlSharesOneEquationForTheGrip) {
  TestModel t = clamped_strip(ElementType::Q4);
  t.control = GripControl::force;
  const DofMap d = make_dof_map(t);
  ASSERT_GE(d.master, 0);
  for (int k : d.top_y) EXPECT_EQ(d.eq[k], d.master);
}

TEST(Assembler, TheInternalForcesOfAnyStateSumToZero) {
  // f_a = ∫ Pᵀ ∇N_a and Σ_a N_a = 1: the internal forces balance, whatever u (translation invariance).
  for (ElementType type : {ElementType::Q4, ElementType::Q8}) {
    const TestModel t = clamped_strip(type);
    const DofMap dofs = make_dof_map(t);
    const NeoHookean law(0.5, 1.0);
    const Assembler assembler(t, dofs, law);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> r(-0.2, 0.2);
    Eigen::VectorXd u(t.mesh.dofs());
    for (int n = 0; n < t.mesh.nodes(); ++n) {
      u(2 * n) = -0.05 * t.mesh.X(0, n) + r(rng);
      u(2 * n + 1) = 0.1 * t.mesh.X(1, n) + r(rng);
    }
    Assembled a;
    ASSERT_TRUE(assembler.assemble(u, {true, false}, a));
    double fx = 0, fy = 0, size = 0;
    for (int n = 0; n < t.mesh.nodes(); ++n) fx += a.f(2 * n), fy += a.f(2 * n + 1), size += std::abs(a.f(2 * n + 1));
    EXPECT_GT(size, 0.1);  // the state is loaded
    EXPECT_NEAR(fx, 0, kRoundOff * size);
    EXPECT_NEAR(fy, 0, kRoundOff * size);
    EXPECT_TRUE(a.symmetric);  // a hyperelastic law
  }
}

TEST(Assembler, TheUndeformedStateHasNoInternalForce) {
  const TestModel t = clamped_strip(ElementType::Q8);
  const DofMap dofs = make_dof_map(t);
  const NeoHookean law(0.5, 1.0);
  const Assembler assembler(t, dofs, law);
  Assembled a;
  ASSERT_TRUE(assembler.assemble(Eigen::VectorXd::Zero(t.mesh.dofs()), {true, false}, a));
  EXPECT_LT(a.f.cwiseAbs().maxCoeff(), kRoundOff);
  EXPECT_EQ(a.K.rows(), dofs.equations);
}

TEST(Assembler, AnInvertedElementIsReportedNotAssembled) {
  const TestModel t = clamped_strip(ElementType::Q4);
  const DofMap dofs = make_dof_map(t);
  const NeoHookean law(0.5, 1.0);
  const Assembler assembler(t, dofs, law);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(t.mesh.dofs());
  for (int n = 0; n < t.mesh.nodes(); ++n) u(2 * n + 1) = -2 * t.mesh.X(1, n);  // y → −y: det F < 0
  Assembled a;
  EXPECT_FALSE(assembler.assemble(u, {true, false}, a));
  EXPECT_NE(a.status, ElementStatus::ok);
  EXPECT_GE(a.element, 0);
}

// Issue 15: the threaded assembly (colours: no two elements of a colour share a node, each colour's
// elements one after the other per entry) gives the serial sums bit for bit. The first four tangent
// assemblies of a model with ≥ 30 000 quadrature points alternate serial and threaded (the timing
// probes in assemble()); a non-symmetric law with sensitivities fills every output.
TEST(Assembler, TheThreadedAssemblyIsTheSerialOneBitForBit) {
  MeshOptions o;
  o.width = 50, o.height = 50, o.nx = 60, o.ny = 60, o.type = ElementType::Q8;  // 32 400 points
  TestModel t;
  t.mesh = make_quarter_mesh(o);
  t.loads = {1};
  t.grip_holds_x = true;
  const DofMap dofs = make_dof_map(t);
  ResponseSurface law = ResponseSurface::preset("paper14", 0.05);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(14);
  c(0) = 0.25, c(1) = 0.1, c(6) = 0.02, c(8) = 0.06, c(9) = 0.03, c(12) = 0.01;
  law.set_coefficients(c);
  const Assembler assembler(t, dofs, law);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> r(-0.01, 0.01);
  Eigen::VectorXd u(t.mesh.dofs());
  for (int n = 0; n < t.mesh.nodes(); ++n) {
    u(2 * n) = -0.05 * t.mesh.X(0, n) + r(rng);
    u(2 * n + 1) = 0.2 * t.mesh.X(1, n) + r(rng);
  }
  const int threads = omp_get_max_threads();
  omp_set_num_threads(2);
  std::vector<Assembled> a(4);
  for (Assembled& x : a) ASSERT_TRUE(assembler.assemble(u, {true, true}, x));
  omp_set_num_threads(threads);
  EXPECT_FALSE(a[0].symmetric);
  auto same = [](const auto& x, const auto& y) { return x.size() == y.size() && (x.array() == y.array()).all(); };
  for (int k = 1; k < 4; ++k) {
    EXPECT_TRUE(same(a[k].f, a[0].f)) << k;
    EXPECT_TRUE(same(Eigen::Map<const Eigen::VectorXd>(a[k].K.valuePtr(), a[k].K.nonZeros()),
                     Eigen::Map<const Eigen::VectorXd>(a[0].K.valuePtr(), a[0].K.nonZeros())))
        << k;
    EXPECT_TRUE(same(a[k].df_dc, a[0].df_dc)) << k;
    EXPECT_TRUE(same(a[k].g_grip, a[0].g_grip)) << k;
    EXPECT_TRUE(same(a[k].h_top, a[0].h_top)) << k;
    EXPECT_EQ(a[k].symmetric, a[0].symmetric);
  }
}

}  // namespace
}  // namespace tricot::fem::detail
