#include "tricot/synth/specimen.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include <Eigen/LU>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/gmsh.hpp"

using namespace tricot;
using namespace tricot::synth;
namespace fs = std::filesystem;

namespace {

/// Pixels are stored as float: two renderings of the same material points agree to float round-off.
constexpr double kFloatTol = 1e-6;
/// The renderer samples the pattern's B-spline table (speckle.hpp's PatternTable): a sub-sample is
/// within 5e-3 of the exact pattern (speckle_test, PatternTable), so a pixel's mean of them too ...
constexpr double kTableTol = 5e-3;
/// ... and the RMS over an image within 1e-4 (measured 4–5e-5 per point; its material points are
/// Newton's to ~1e-6 of an element, which moves a gray level by ~1e-6).
constexpr double kTableRms = 1e-4;
/// Material points recovered by Newton on the deformed Q8 map (stopping at |Δξ| < 1e-13).
constexpr double kPointTol = 1e-9;

constexpr double kW = 20, kH = 30;  // quarter, mm

fem::Mesh quarter(fem::ElementType type = fem::ElementType::Q8) {
  fem::MeshOptions m;
  m.width = kW, m.height = kH, m.nx = 4, m.ny = 5, m.type = type, m.grading = 0.5;
  return fem::make_quarter_mesh(m);
}

/// The nodal values of a displacement field u(X) of the quarter.
template <class F>
Eigen::VectorXd nodal(const fem::Mesh& mesh, F u) {
  Eigen::VectorXd v(mesh.dofs());
  for (int n = 0; n < mesh.nodes(); ++n) v.segment<2>(2 * n) = u(Vec2(mesh.X.col(n)));
  return v;
}

SpecimenImageOptions float_images(int width, int height) {
  SpecimenImageOptions o;
  o.camera = {0.1, width, height};
  o.speckle.subsamples = 2;
  o.bits = 32;
  return o;
}

/// Pixels whose whole square lies inside (or outside) |x| < a, |y| < b in specimen mm.
bool square_inside(const Camera& c, int x, int y, double a, double b) {
  const Vec2 X = c.to_specimen(Vec2(x, y));
  const double h = 0.5 * c.mm_per_px + 1e-9;
  return std::abs(X(0)) + h < a && std::abs(X(1)) + h < b;
}
bool square_outside(const Camera& c, int x, int y, double a, double b) {
  const Vec2 X = c.to_specimen(Vec2(x, y));
  const double h = 0.5 * c.mm_per_px + 1e-9;
  return std::abs(X(0)) - h > a || std::abs(X(1)) - h > b;
}

}  // namespace

TEST(Camera, PutsTheSpecimenCentreAtTheImageCentreWithYUp) {
  const Camera c{0.05, 600, 401};
  EXPECT_EQ(c.centre_px(), Vec2(299.5, 200));
  EXPECT_TRUE(c.to_specimen(Vec2(299.5, 200)).isZero());
  EXPECT_TRUE(c.to_specimen(Vec2(309.5, 190)).isApprox(Vec2(0.5, 0.5)));  // right and up on screen
  const Vec2 X(-3.25, 7.5);
  EXPECT_TRUE(c.to_specimen(c.to_pixel(X)).isApprox(X));
}

TEST(SpecimenImageOptions, DefaultsAreValidAndABadBitDepthIsRejectedWithItsKey) {
  EXPECT_NO_THROW(SpecimenImageOptions{}.validate());
  SpecimenImageOptions o;
  o.bits = 12;
  try {
    o.validate();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "images.bits");
  }
  o = {};
  o.camera.mm_per_px = 0;
  EXPECT_THROW(o.validate(), InputError);
}

TEST(FullSpecimen, MirrorsTheQuarterIntoEveryQuadrantBothWays) {
  const fem::Mesh mesh = quarter();
  // A quadratic field with the quarter's symmetries (u_x = 0 on X = 0, u_y = 0 on Y = 0): Q8
  // serendipity elements (straight sides) reproduce it exactly.
  const auto u = [](const Vec2& X) {
    return Vec2(-0.1 * X(0) + 0.002 * X(0) * X(1), 0.2 * X(1) + 0.004 * X(0) * X(0));
  };
  const FullSpecimen body(mesh, nodal(mesh, u));
  const auto u_full = [&](const Vec2& X) {  // u(−X, Y) = (−u_X, u_Y)(X, Y), u(X, −Y) = (u_X, −u_Y)(X, Y)
    const Vec2 s(X(0) < 0 ? -1 : 1, X(1) < 0 ? -1 : 1);
    return Vec2(u(X.cwiseAbs()).cwiseProduct(s));
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-kW, kW), uy(-kH, kH);
  fem::Location hint;
  for (int k = 0; k < 200; ++k) {
    const Vec2 X(ux(rng), uy(rng));
    const auto d = body.displacement(X);
    ASSERT_TRUE(d.has_value());
    EXPECT_LT((*d - u_full(X)).norm(), kPointTol);
    const auto back = body.material_point(X + u_full(X), k % 2 ? &hint : nullptr);
    ASSERT_TRUE(back.has_value()) << X.transpose();
    EXPECT_LT((*back - X).norm(), kPointTol) << X.transpose();
  }
  // Outside: beside the narrowed strip and beyond the grips.
  EXPECT_FALSE(body.material_point(Vec2(-0.95 * kW, 0)).has_value());  // u_X(W) = −2 mm at Y = 0
  EXPECT_FALSE(body.material_point(Vec2(0, -1.25 * kH)).has_value());
  EXPECT_FALSE(body.displacement(Vec2(kW + 0.1, 0)).has_value());
}

TEST(SpecimenRenderer, HomogeneousStretchShowsTheSpeckleAtXOverLambda) {
  for (auto type : {fem::ElementType::Q8, fem::ElementType::Q4}) {
    const fem::Mesh mesh = quarter(type);
    const double lx = 0.9, ly = 1.25;  // a sliding grip's uniform state: x = λ X
    const Eigen::VectorXd u = nodal(mesh, [&](const Vec2& X) { return Vec2((lx - 1) * X(0), (ly - 1) * X(1)); });
    const SpecimenImageOptions o = float_images(420, 300);  // 42 mm wide: background beside the 36 mm strip
    const SpecimenRenderer r(mesh, o);
    const image::Image img = r.render(u);
    const Camera& c = o.camera;
    // The same pattern through the analytic inverse motion X = x / λ (speckle.hpp's renderer).
    const image::Image expected = render(r.pattern(), c.width, c.height, [&](const Vec2& x_px) {
      const Vec2 x = c.to_specimen(x_px);
      return c.to_pixel(Vec2(x(0) / lx, x(1) / ly));
    });
    int inside = 0, outside = 0;
    double s2 = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        if (square_inside(c, x, y, lx * kW, ly * kH)) {
          ++inside;
          ASSERT_NEAR(img.at(x, y), expected.at(x, y), kTableTol) << x << ", " << y;
          s2 += std::pow(img.at(x, y) - expected.at(x, y), 2);
        } else if (square_outside(c, x, y, lx * kW, ly * kH)) {
          ++outside;
          ASSERT_EQ(img.at(x, y), static_cast<float>(o.background)) << x << ", " << y;
        } else {  // the edge: part speckle, part background
          ASSERT_GE(img.at(x, y), std::min(o.background, o.speckle.background) - kTableTol);
        }
      }
    EXPECT_GT(inside, 100000);
    EXPECT_GT(outside, 10000);
    EXPECT_LT(std::sqrt(s2 / inside), kTableRms);
  }
}

namespace {

/// The renderer before issue 32, kept as the reference: per sub-sample, the material point by
/// FullSpecimen::material_point (Newton in the located element of the deformed quarter) and the
/// pattern's exact intensity (every neighbouring blob). Also counts the pixels whose sub-samples the
/// specimen's outline separates.
image::Image old_render(const SpecimenRenderer& r, const fem::Mesh& mesh, const Eigen::VectorXd& u,
                        int* edge = nullptr) {
  const FullSpecimen body(mesh, u);
  const SpecimenImageOptions& o = r.options();
  const Camera& c = o.camera;
  const int s = o.speckle.subsamples;
  image::Image img(c.width, c.height, 0.0f, 1.0);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      double sum = 0;
      int on = 0;
      for (int b = 0; b < s; ++b)
        for (int a = 0; a < s; ++a) {
          const Vec2 xs(x - 0.5 + (a + 0.5) / s, y - 0.5 + (b + 0.5) / s);
          const auto X = body.material_point(c.to_specimen(xs));
          sum += X ? r.pattern().intensity(c.to_pixel(*X)) : o.background;
          on += X.has_value();
        }
      if (edge) *edge += on > 0 && on < s * s;
      img.at(x, y) = static_cast<float>(sum / (s * s));
    }
  return img;
}

double rms_difference(const image::Image& a, const image::Image& b) {
  double s2 = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) s2 += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
  return std::sqrt(s2 / double(a.pixels.size()));
}

}  // namespace

TEST(OldRenderer, GivesTheImageOfEveryElementDrawingItsOwnAcrossANeckedEdgeAndTheGrips) {
  // The renderer draws element by element (Newton from the previous sub-sample, Hermite between
  // anchors); the old one located every sub-sample in the deformed mesh: the same image, curved Q8
  // sides, the outline and the grips included.
  const fem::Mesh mesh = quarter();
  const Eigen::VectorXd u = nodal(mesh, [](const Vec2& X) {
    const double eta = X(1) / kH;  // the strip necks at mid-height, not at the clamped grip
    return Vec2(-0.15 * X(0) * (1 - eta * eta), 0.3 * X(1) + 0.002 * X(0) * X(0) * eta);
  });
  for (int s : {1, 2, 3}) {
    SpecimenImageOptions o = float_images(180, 280);
    o.camera.mm_per_px = 0.3;  // 54 × 84 mm: background beside the 40 mm strip and beyond its 78 mm length
    o.speckle.subsamples = s;
    const SpecimenRenderer r(mesh, o);
    const image::Image img = r.render(u);
    int edge = 0;
    const image::Image old = old_render(r, mesh, u, &edge);
    for (int y = 0; y < o.camera.height; ++y)
      for (int x = 0; x < o.camera.width; ++x)
        ASSERT_NEAR(img.at(x, y), old.at(x, y), kTableTol) << x << ", " << y << " s " << s;
    EXPECT_LT(rms_difference(img, old), kTableRms) << s;
    // Pixels whose sub-samples the boundary separates (hundreds along the four edges) were compared too.
    if (s > 1) {
      EXPECT_GT(edge, 300);
    }
  }
}

TEST(OldRenderer, GivesTheDemosKnitFramesWithinTheirNoise) {
  // The demo's camera set-up (knit of 5 px stitches, 2 × 2 sub-samples, 8 bit, noise of 1 gray level)
  // on a quarter stretched 1.6× and necked: the 8-bit frames, same noise seed, differ by far less than
  // the noise σ (the float pictures by 0.003 gray level RMS, 1280 × 1024: synth_benchmark).
  fem::MeshOptions m;
  m.width = 55, m.height = 55, m.nx = 12, m.ny = 10, m.grading = 0.5, m.grading_x = 0.5;
  const fem::Mesh mesh = fem::make_quarter_mesh(m);
  const Eigen::VectorXd u = nodal(mesh, [](const Vec2& X) {
    const double eta = X(1) / 55;
    return Vec2(-0.2 * X(0) * (1 - eta * eta), 0.6 * X(1) + 0.002 * X(0) * X(0) * eta);
  });
  SpecimenImageOptions o;
  o.camera = {0.5, 320, 420};
  o.speckle.texture = Texture::knit;
  o.speckle.radius = 2.5;
  o.speckle.subsamples = 2;
  o.speckle.wale_angle_deg = -90;
  o.noise = 1;
  o.bits = 8;
  const SpecimenRenderer r(mesh, o);
  const image::Image frame = r.render(u, 11);
  image::Image old = old_render(r, mesh, u);
  old = add_noise(old, o.noise / 255, 11);
  for (float& p : old.pixels) p = static_cast<float>(std::clamp(std::round(p * 255.0), 0.0, 255.0));
  EXPECT_LT(rms_difference(frame, old), 0.1 * o.noise);  // gray levels: a pixel differs by one level at most ...
  int off = 0;
  for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
    ASSERT_LE(std::abs(frame.pixels[i] - old.pixels[i]), 1.0f);
    off += frame.pixels[i] != old.pixels[i];
  }
  EXPECT_LT(off, int(frame.pixels.size() / 100));  // ... where rounding falls the other way: under 1 %
}

TEST(SpecimenRenderer, ReferenceImageShowsThePatternWhereItIsAndFlatGrayBeyondTheGrips) {
  const fem::Mesh mesh = quarter();
  const SpecimenImageOptions o = float_images(300, 700);  // 70 mm tall: the 60 mm specimen and grips
  const SpecimenRenderer r(mesh, o);
  const image::Image img = r.render(Eigen::VectorXd());
  const image::Image expected = render(r.pattern(), 300, 700, no_motion);
  int inside = 0, outside = 0;
  for (int y = 0; y < 700; ++y)
    for (int x = 0; x < 300; ++x) {
      if (square_inside(o.camera, x, y, kW, kH)) {
        ++inside;
        ASSERT_NEAR(img.at(x, y), expected.at(x, y), kTableTol);
      } else if (square_outside(o.camera, x, y, kW, kH)) {
        ++outside;
        ASSERT_EQ(img.at(x, y), static_cast<float>(o.background));
      }
    }
  EXPECT_EQ(inside, 300 * 598);  // rows within 30 mm of the centre row 349.5, less the edge rows
  EXPECT_EQ(outside, 300 * 98);  // rows more than 30 mm + ½ px away
}

TEST(SpecimenRenderer, PatternIsNotTheQuartersMirrored) {
  // Mirroring X back to its own quadrant keeps the speckle of the whole specimen: the left half of the
  // image is not the right half flipped (it would be, gray for gray, if the quarter's X were used).
  const fem::Mesh mesh = quarter();
  const SpecimenRenderer r(mesh, float_images(200, 200));
  const Eigen::VectorXd u = nodal(mesh, [](const Vec2& X) { return Vec2(-0.1 * X(0), 0.3 * X(1)); });
  const image::Image img = r.render(u);
  double diff = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 100; ++x) diff += std::abs(img.at(x, y) - img.at(199 - x, y));
  EXPECT_GT(diff / (100 * 200), 0.1);  // mean |difference| of two independent speckles (contrast 0.8)
}

TEST(SpecimenRenderer, QuantisesToTheBitDepthAndAddsNoiseOfTheGivenSigma) {
  const fem::Mesh mesh = quarter();
  SpecimenImageOptions o = float_images(160, 160);
  const image::Image exact = SpecimenRenderer(mesh, o).render(Eigen::VectorXd());
  for (int bits : {8, 16}) {
    o.bits = bits;
    o.noise = 0;
    const double levels = bits == 8 ? 255 : 65535;
    const image::Image img = SpecimenRenderer(mesh, o).render(Eigen::VectorXd());
    EXPECT_EQ(img.full_scale, levels);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) ASSERT_EQ(img.pixels[i], std::round(exact.pixels[i] * levels));

    o.noise = 3;  // gray levels
    o.threads = 1;
    const image::Image noisy = SpecimenRenderer(mesh, o).render(Eigen::VectorXd(), 7);
    o.threads = 2;
    const image::Image again = SpecimenRenderer(mesh, o).render(Eigen::VectorXd(), 7);
    EXPECT_EQ(noisy.pixels, again.pixels);  // the noise does not depend on the thread count
    double s2 = 0;
    for (std::size_t i = 0; i < img.pixels.size(); ++i) s2 += std::pow(noisy.pixels[i] - img.pixels[i], 2);
    // 25 600 samples: the sample σ is within 3 % of 3 (plus 1/12 level² of variance per rounding).
    EXPECT_NEAR(std::sqrt(s2 / double(img.pixels.size())), std::sqrt(9 + 2.0 / 12), 0.09);
  }
}

namespace {

// A whole 40 × 20 mm plate centred on the origin with a 4 mm hole off its axes (a one-sided pull's
// specimen: no symmetry for the camera to mirror).
const char* kPlateWithHole = R"(
SetFactory("OpenCASCADE");
Rectangle(1) = {-20, -10, 0, 40, 20};
Disk(2) = {6, 2, 0, 4, 4};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
Physical Surface("plate") = {3};
)";

// Signed distance (mm) from a material point to the plate's outline: > 0 inside the material.
double inside_plate(const Vec2& X) {
  const double box = std::min(20 - std::abs(X(0)), 10 - std::abs(X(1)));
  return std::min(box, (X - Vec2(6, 2)).norm() - 4);
}

}  // namespace

TEST(SpecimenRenderer, AWholeMeshOfEveryTypeWithAHoleShowsTheSpeckleThroughTheInverseMotion) {
  // Extent::whole: the mesh is the specimen, nothing is mirrored. An affine motion x = F X + t (a
  // stretch, a shear and the drift of a one-sided pull) is exact in every element type, so each pixel
  // shows the pattern at X = F⁻¹(x − t); the hole and the surroundings show the background.
  const fs::path dir = test::scratch_dir("specimen_whole");
  { std::ofstream(dir / "plate.geo") << kPlateWithHole; }
  Mat2 F;
  F << 1.15, 0.05, 0.0, 0.92;
  const Vec2 t(1.5, -0.8);
  const Mat2 F_inv = F.inverse();
  for (const auto& [order, quads] : {std::pair{1, false}, {2, false}, {1, true}, {2, true}}) {
    fem::GeometryMeshOptions g;
    g.size = 1.5, g.order = order, g.quads = quads;
    const fem::Mesh mesh = fem::mesh_geometry((dir / "plate.geo").string(), g);
    const Eigen::VectorXd u = nodal(mesh, [&](const Vec2& X) { return Vec2(F * X + t - X); });
    const SpecimenImageOptions o = float_images(560, 260);  // 56 × 26 mm: background all round the plate
    const SpecimenRenderer r(mesh, o, Extent::whole);
    const image::Image img = r.render(u);
    const Camera& c = o.camera;
    const image::Image expected = render(r.pattern(), c.width, c.height, [&](const Vec2& x_px) {
      return c.to_pixel(F_inv * (c.to_specimen(x_px) - t));
    });
    // A pixel's square maps back within this of its centre's material point; straight element sides
    // leave the hole's outline up to s²/(8 r) = 0.07 mm off the circle.
    const double reach = 0.5 * std::sqrt(2.0) * c.mm_per_px * F_inv.norm() + 0.08;
    int inside = 0, outside = 0;
    double s2 = 0;
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        const double d = inside_plate(F_inv * (c.to_specimen(Vec2(x, y)) - t));
        if (d > reach) {
          ++inside;
          ASSERT_NEAR(img.at(x, y), expected.at(x, y), kTableTol) << x << ", " << y << " " << fem::to_string(mesh.type);
          s2 += std::pow(img.at(x, y) - expected.at(x, y), 2);
        } else if (d < -reach) {
          ++outside;
          ASSERT_EQ(img.at(x, y), static_cast<float>(o.background))
              << x << ", " << y << " " << fem::to_string(mesh.type);
        }
      }
    // The deformed plate covers 46 × 18.4 mm less the hole's 0.53 · 50 mm²: about 81 000 px; the
    // background about 56 000 px (of 145 600), the hole about 2 600.
    EXPECT_GT(inside, 75000) << fem::to_string(mesh.type);
    EXPECT_GT(outside, 55000) << fem::to_string(mesh.type);
    EXPECT_LT(std::sqrt(s2 / inside), kTableRms) << fem::to_string(mesh.type);
    // The hole's centre is background.
    const Vec2 hole = c.to_pixel(F * Vec2(6, 2) + t);
    EXPECT_EQ(img.at(int(std::lround(hole(0))), int(std::lround(hole(1)))), static_cast<float>(o.background));
  }
}
