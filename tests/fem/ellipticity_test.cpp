// Strong ellipticity (the acoustic tensor) of a law's tangent: closed forms for the isotropic law, the
// fabric frame's loss of it in shear, and the FE's note when an element fails where the law has lost it.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>

#include "tricot/fem/corotational.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/fem/reference_fabric.hpp"
#include "tricot/fem/response_surface.hpp"
#include "tricot/fem/rig.hpp"
#include "tricot/fem/solver.hpp"

using namespace tricot;
using namespace tricot::fem;

namespace {

LawOutput at(const Law& law, const Mat2& F) {
  LawInput in;
  in.F = F;
  LawOutput out;
  law.evaluate(in, LawRequest{}, out);
  return out;
}

/// The stretch U with Green–Lagrange strain E: U = (I + 2E)^½.
Mat2 stretch(const Mat2& E) {
  const Eigen::SelfAdjointEigenSolver<Mat2> es(Mat2::Identity() + 2 * E);
  return es.eigenvectors() * es.eigenvalues().cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
}

// Small strain, isotropic (K, G): Q(N) = (K + G) N⊗N + G (I − N⊗N) for every N, so the smallest
// eigenvalue is G whatever the direction; a rigid rotation changes nothing (objectivity).
TEST(StrongEllipticity, IsTheShearModulusOfTheIsotropicLawAtRestAndAfterARotation) {
  const CorotationalOrthotropic law = CorotationalOrthotropic::isotropic(0.3, 1.1);
  EXPECT_NEAR(strong_ellipticity(at(law, Mat2::Identity()).A).min_eigenvalue, 0.3, 1e-12);
  const Mat2 R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  EXPECT_NEAR(strong_ellipticity(at(law, R).A).min_eigenvalue, 0.3, 1e-12);
}

// Orthotropic at rest, D66 far below D11, D22 and D12 = 0: Q(e1) = diag(D11, D66), and for N at angle
// t, λ_min(t) ≥ D66 with equality at t = 0 and 90°, so the minimum is D66 across x or y.
TEST(StrongEllipticity, FindsTheWeakestDirectionOfAnOrthotropicLaw) {
  const CorotationalOrthotropic law(2.0, 1.0, 0.0, 0.05);
  const Ellipticity e = strong_ellipticity(at(law, Mat2::Identity()).A);
  EXPECT_NEAR(e.min_eigenvalue, 0.05, 1e-9);
  EXPECT_TRUE(std::abs(e.angle_deg) < 1e-3 || std::abs(e.angle_deg - 90) < 1e-3 || std::abs(e.angle_deg - 180) < 1e-3)
      << e.angle_deg;
}

// The fabric frame (docs/theory/fabric.md §3, T12 = 2 G_s E_CW in the corotated frame) loses strong
// ellipticity in pure shear of the material axes between E_CW = 0.2 and 0.3, for the reference knit;
// the tangent it is computed from agrees with central differences of P there (so the loss is the
// law's, not a tangent error).
TEST(StrongEllipticity, TheFabricFrameLosesItInPureShearBeyondAQuarter) {
  const ReferenceFabric knit;
  auto lambda = [&](double s) {
    Mat2 E;
    E << 0, s, s, 0;
    return strong_ellipticity(at(knit, stretch(E)).A).min_eigenvalue;
  };
  EXPECT_GT(lambda(0.1), 0);
  EXPECT_GT(lambda(0.2), 0);
  EXPECT_LT(lambda(0.3), 0);
  EXPECT_LT(lambda(0.4), lambda(0.3));
  Mat2 E;
  E << 0, 0.3, 0.3, 0;
  const Mat2 F = stretch(E);
  Mat4 A_fd;
  const double h = 1e-6;
  for (int k = 0; k < 4; ++k) {
    Mat2 dF = Mat2::Zero();
    dF(k / 2, k % 2) = h;
    const Mat2 dP = (at(knit, F + dF).P - at(knit, F - dF).P) / (2 * h);
    for (int i = 0; i < 4; ++i) A_fd(i, k) = dP(i / 2, i % 2);
  }
  EXPECT_NEAR(strong_ellipticity(A_fd).min_eigenvalue, lambda(0.3), 1e-8);
}

// The §4 rig's wale pull held at εC = 0.7 (110 mm, 120 Q8) with the law the domain-restricted LM
// reached on the campaign (docs/validation.md §9): element 107, where the guide ends, shears to
// E_CW ≈ −0.85 and the law has lost strong ellipticity there; the step that fails says so.
TEST(StrongEllipticity, AFailedRigStepNamesTheElementWhereTheLawLostIt) {
  RigOptions o;
  o.name = "wale-70";
  o.side = 110, o.pull = PullDirection::wale, o.transverse_strain = 0.7, o.pull_strain = 0.65, o.steps = 21;
  o.nx = 12, o.ny = 10;
  ResponseSurface law = ResponseSurface::preset("paper14", 0.05);
  Eigen::VectorXd c(14);
  c << 0.303400, -0.0184825, 0.0201968, 0.0319611, 0.0287064, 0.0181938, -0.0145969, 0.344064, 0.160362, -0.0495555,
      0.0597661, 0.158003, 0.0374856, 0.127104;
  law.set_coefficients(c);
  const SimulationResult r = simulate(make_rig_test(o), law);
  ASSERT_FALSE(r.usable()) << r.message;
  EXPECT_NE(r.message.find("element 107 inverted"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("not strongly elliptic in element 107"), std::string::npos) << r.message;
}

}  // namespace
