#include "tricot/image/bspline.hpp"

#include <gtest/gtest.h>

#include <random>

#include "testing/fd_check.hpp"

using namespace tricot;
using namespace tricot::image;

namespace {

/// Coefficients are stored as float: values of order 100 interpolate to about 1e-5 relative.
constexpr double kFloatTol = 2e-4;

Image random_image(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 255);
  Image img(w, h, 0.0f, 255.0);
  for (auto& p : img.pixels) p = u(rng);
  return img;
}

/// A cubic polynomial: cubic B-splines reproduce it exactly away from the mirrored border.
double cubic(double x, double y) { return 20 + 0.5 * x - 0.3 * y + 0.01 * x * y + 2e-4 * x * x * x - 1e-4 * y * y * y; }
double cubic_dx(double x, double y) { return 0.5 + 0.01 * y + 6e-4 * x * x; }
double cubic_dy(double x, double y) { return -0.3 + 0.01 * x - 3e-4 * y * y; }

}  // namespace

TEST(BSplineImage, InterpolatesEveryPixelExactly) {
  const Image img = random_image(37, 23, 1);
  const BSplineImage f(img);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) EXPECT_NEAR(f.value(x, y), img.at(x, y), kFloatTol * 255) << x << "," << y;
}

TEST(BSplineImage, ReproducesACubicPolynomialAndItsGradientInsideTheImage) {
  Image img(60, 50);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.at(x, y) = static_cast<float>(cubic(x, y));
  const BSplineImage f(img);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ux(20, 40), uy(18, 32);
  for (int k = 0; k < 50; ++k) {
    const double x = ux(rng), y = uy(rng);
    const Sample s = f.sample(x, y);
    EXPECT_NEAR(s.value, cubic(x, y), kFloatTol * 50);
    EXPECT_NEAR(f.value(x, y), s.value, 1e-4);
    EXPECT_NEAR(s.dx, cubic_dx(x, y), kFloatTol * 10);
    EXPECT_NEAR(s.dy, cubic_dy(x, y), kFloatTol * 10);
  }
}

TEST(BSplineImage, GradientMatchesFiniteDifferencesOfTheInterpolant) {
  const Image img = random_image(30, 30, 3);
  const BSplineImage f(img);
  // Float evaluation: central differences with h = 1e-3 px are good to about 1e-3 relative.
  constexpr double kFdTol = 5e-3;
  for (Eigen::Vector2d p : {Eigen::Vector2d(10.3, 12.7), Eigen::Vector2d(0.2, 28.9), Eigen::Vector2d(15.5, 15.5)}) {
    auto value = [&](const Eigen::VectorXd& q) { return Eigen::VectorXd::Constant(1, f.value(q(0), q(1))); };
    const Sample s = f.sample(p(0), p(1));
    Eigen::MatrixXd J(1, 2);
    J << s.dx, s.dy;
    EXPECT_TRUE(test::JacobianMatches(value, p, J, kFdTol, 1e-3));
  }
}

TEST(BSplineImage, NodeGradientEqualsTheSampledGradientAtPixelCentres) {
  const Image img = random_image(25, 20, 4);
  const BSplineImage f(img);
  const Gradient g = gradient(f);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const Sample s = f.sample(x, y);
      EXPECT_NEAR(g.dx.at(x, y), s.dx, 1e-3);
      EXPECT_NEAR(g.dy.at(x, y), s.dy, 1e-3);
    }
}

TEST(BSplineImage, ConstantImageHasConstantValueAndZeroGradient) {
  const BSplineImage f(Image(12, 9, 7.0f));
  const Sample s = f.sample(5.37, 3.91);
  EXPECT_NEAR(s.value, 7.0, 1e-5);
  EXPECT_NEAR(s.dx, 0.0, 1e-5);
  EXPECT_NEAR(s.dy, 0.0, 1e-5);
}
