#include "tricot/lab/specimen.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::lab;

namespace {
// Exact arithmetic on small numbers: only rounding remains.
constexpr double exact = 1e-12;
}  // namespace

TEST(Specimen, FoldsTheFourQuadrantsIntoTheQuarterWithMatchingDisplacementSigns) {
  dic::PhysicalFrame frame;  // y up on screen
  frame.mm_per_px = 0.1;
  frame.centre_px = {500, 400};
  SpecimenGeometry g{100, 60, 0};
  // The same material offset (20 mm, 10 mm) from the centre in each quadrant, image y pointing down.
  const std::vector<Vec2> x{{700, 300}, {300, 300}, {300, 500}, {700, 500}};
  const FoldedPoints f = fold_to_quarter(frame, g, x);
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f.quadrant, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(f.outside, 0);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(f.X[k](0), 20, exact);
    EXPECT_NEAR(f.X[k](1), 10, exact);
    // a symmetric stretch u = (0.1 X, 0.2 Y) in specimen axes, seen in image px (y down)
    const Vec2 P = frame.point(x[k]);
    const Vec2 u_px(0.1 * P(0) / 0.1, -0.2 * P(1) / 0.1);
    const Vec2 u = f.displacement(k, u_px);
    EXPECT_NEAR(u(0), 2, exact) << "quadrant " << f.quadrant[k];
    EXPECT_NEAR(u(1), 2, exact) << "quadrant " << f.quadrant[k];
  }
}

TEST(Specimen, PointsOutsideTheSpecimenAreCountedAndReported) {
  dic::PhysicalFrame frame;
  frame.mm_per_px = 0.1;
  SpecimenGeometry g{100, 60, 0};
  const FoldedPoints f = fold_to_quarter(frame, g, {{0, 0}, {499, 0}, {501, 0}, {0, -301}});
  EXPECT_EQ(f.inside, (std::vector<bool>{true, true, false, false}));
  EXPECT_EQ(f.outside, 2);
  EXPECT_EQ(f.outside_report(g), "2 of 4 points lie outside the 100 × 60 mm specimen");
  g.tolerance_mm = 0.2;
  EXPECT_EQ(fold_to_quarter(frame, g, {{501, 0}}).outside, 0);
}

TEST(Specimen, SigmaTurnsWithTheCameraAndScales) {
  dic::PhysicalFrame frame;
  frame.mm_per_px = 0.05;
  frame.angle_deg = 90;  // specimen X along the image's −y
  const FoldedPoints f = fold_to_quarter(frame, {}, {{0, 0}});
  const Vec2 s = f.sigma(0, {0.02, 0.04});
  EXPECT_NEAR(s(0), 0.05 * 0.04, exact);
  EXPECT_NEAR(s(1), 0.05 * 0.02, exact);
}

TEST(Specimen, ScaleOfZeroIsAnError) {
  dic::PhysicalFrame frame;
  frame.mm_per_px = 0;
  try {
    fold_to_quarter(frame, {}, {{0, 0}});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "physical.mm_per_px: out of range (got 0, expected > 0 mm/px)");
  }
}

TEST(Specimen, ScaleFromTwoPointsAKnownDistanceApart) {
  EXPECT_NEAR(scale_from_points({100, 100}, {400, 500}, 50), 0.1, exact);
  EXPECT_THROW(scale_from_points({100, 100}, {100, 100}, 50), InputError);
  EXPECT_THROW(scale_from_points({100, 100}, {400, 500}, 0), InputError);
}

TEST(Specimen, NonPositiveGeometryIsAnError) {
  SpecimenGeometry g;
  g.width_mm = 0;
  EXPECT_THROW(g.validate(), InputError);
}

TEST(Specimen, FoldedSequenceKeepsInsidePointsMeasuredInEveryStepWithTheirSigma) {
  // A hand-made sequence: 3 points, 3 images, uniform stretch v = 0.01·Y per step in specimen axes.
  dic::PhysicalFrame frame;
  frame.mm_per_px = 0.1;
  frame.centre_px = {100, 100};
  const SpecimenGeometry g{20, 30, 0};  // quarter 10 × 15 mm
  dic::SequenceResult s;
  s.grid = {{{150, 50}, 0, 0}, {{50, 150}, 0, 0}, {{400, 100}, 0, 0}};  // (5, 5), (−5, −5), outside
  for (int k = 0; k < 3; ++k) {
    dic::TrackedFrame f;
    for (const auto& p : s.grid) {
      const Vec2 X = frame.point(p.x);
      f.x.push_back(p.x + Vec2(0, -0.01 * k * X(1) / 0.1));  // v up = image y down
      f.sigma.push_back(Vec2(0.02, 0.03) * std::sqrt(double(k)));
      f.status.push_back(dic::PointStatus::ok);
    }
    s.frames.push_back(f);
  }
  const QuarterField q = fold_sequence(s, frame, g, FieldKind::cumulative);
  EXPECT_EQ(q.point_ids, (std::vector<int>{0, 1}));
  EXPECT_EQ(q.outside, 1);
  EXPECT_EQ(q.incomplete, 0);
  ASSERT_EQ(q.u.rows(), 2);
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(q.X[a](1), 5, exact);
    EXPECT_NEAR(q.v(1, a), 0.02 * 5, exact);  // step 2: both quadrants give +v in the quarter
    EXPECT_NEAR(q.u(1, a), 0, exact);
    EXPECT_NEAR(q.sigma_v(1, a), 0.1 * 0.03 * std::sqrt(2.0), exact);
  }
  const auto grip = grip_from_field(q, g);
  EXPECT_NEAR(grip[1], 0.02 * 15, exact);
  s.frames[2].status[1] = dic::PointStatus::lost;
  EXPECT_EQ(fold_sequence(s, frame, g, FieldKind::cumulative).incomplete, 1);
  EXPECT_THROW(fold_sequence(s, frame, g, FieldKind::incremental), InputError);
}
