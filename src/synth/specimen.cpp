// Synthetic images of the deformed full specimen (see specimen.hpp).
#include "tricot/synth/specimen.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <string>

#include "tricot/core/error.hpp"
#include "tricot/fem/element.hpp"

namespace tricot::synth {

namespace {

// As fem::PointLocator: an element spans 2 in ξ, so 2e-9 is 1e-9 of its size.
constexpr double kXiTolerance = 2e-9;
// Newton on the isoparametric map stops when |Δξ| falls below this (well under kXiTolerance).
constexpr double kNewtonTolerance = 1e-13;
// From a neighbouring subsample's ξ Newton needs 2–3 iterations; more means another element.
constexpr int kNewtonIterations = 12;
// Beyond |ξ| = 5 (two element sizes away) the extrapolated map is not trusted: ask the locator.
constexpr double kFarXi = 5;

[[noreturn]] void bad(const std::string& key, double got, const char* expected) {
  throw InputError(Location{"", 0, key}, "out of range", format_number(got), expected);
}

// The reflection that takes a point of the full specimen into the first quadrant (and back).
Vec2 quadrant_signs(const Vec2& x) { return {x(0) < 0 ? -1.0 : 1.0, x(1) < 0 ? -1.0 : 1.0}; }

}  // namespace

void Camera::validate() const {
  if (!(mm_per_px > 0) || !std::isfinite(mm_per_px)) bad("camera.mm_per_px", mm_per_px, "> 0 mm/px");
  if (width < 8 || width > 20000) bad("camera.width", width, "8 to 20000 px");
  if (height < 8 || height > 20000) bad("camera.height", height, "8 to 20000 px");
}

void SpecimenImageOptions::validate() const {
  camera.validate();
  speckle.validate();
  if (!(background >= 0 && background <= 1)) bad("images.background", background, "0 to 1");
  if (!(noise >= 0) || !std::isfinite(noise)) bad("images.noise", noise, ">= 0 gray levels");
  if (bits != 8 && bits != 16 && bits != 32) bad("images.bits", bits, "8, 16 or 32 (float)");
  if (threads < 0 || threads > 1024) bad("images.threads", threads, "0 to 1024");
}

// ---------------------------------------------------------------------------------------------------
// FullSpecimen

FullSpecimen::FullSpecimen(const fem::Mesh& quarter, const Eigen::VectorXd& u)
    : mesh_(&quarter),
      u_(u),
      X_flat_(Eigen::Map<const Eigen::VectorXd>(quarter.X.data(), quarter.dofs())),
      x_(quarter.X),
      current_(quarter, u.size() ? &u_ : nullptr),
      reference_(quarter) {
  assert(u.size() == 0 || u.size() == quarter.dofs());
  if (u_.size())
    for (int n = 0; n < quarter.nodes(); ++n) x_.col(n) += u_.segment<2>(2 * n);
  // Sides on the quarter's edges. Those on the free edge x = W or the grip y = H are the specimen's
  // outline; the others lie on lines of symmetry, inside the full specimen. Side k joins corners k and
  // k + 1 (0: ξ₂ = −1, 1: ξ₁ = 1, 2: ξ₂ = 1, 3: ξ₁ = −1).
  enum : unsigned char { kRight = 1, kTop = 2, kLeft = 4, kBottom = 8 };
  std::vector<unsigned char> edge(quarter.nodes(), 0);
  for (int n : quarter.right) edge[n] |= kRight;
  for (int n : quarter.top) edge[n] |= kTop;
  for (int n : quarter.left) edge[n] |= kLeft;
  for (int n : quarter.bottom) edge[n] |= kBottom;
  outer_sides_.assign(quarter.elements(), 0);
  const bool q8 = quarter.type == fem::ElementType::Q8;
  for (int e = 0; e < quarter.elements(); ++e) {
    const auto& c = quarter.connectivity[e];
    for (int k = 0; k < 4; ++k) {
      const int a = c[k], b = c[(k + 1) % 4];
      const unsigned common = edge[a] & edge[b];
      if (common & (kRight | kTop)) outer_sides_[e] |= 1 << k;
      if (!common) continue;
      // The deformed quarter's largest x and y lie on its boundary. A Q8 side is a parabola through its
      // end and mid-side nodes, which passes the largest of them by at most |x_a − 2x_m + x_b|/8.
      for (int i = 0; i < 2; ++i) {
        const double xa = x_(i, a), xb = x_(i, b), xm = q8 ? x_(i, c[4 + k]) : 0.5 * (xa + xb);
        reach_(i) = std::max(reach_(i), std::max({xa, xb, xm}) + std::abs(xa - 2 * xm + xb) / 8);
      }
    }
  }
}

FullSpecimen::Found FullSpecimen::newton_in_element(int e, const Vec2& q, Vec2& xi) const {
  const int n = fem::nodes_per_element(mesh_->type);
  const auto& c = mesh_->connectivity[e];
  for (int it = 0; it < kNewtonIterations; ++it) {
    const fem::ShapeValues s = fem::shape(mesh_->type, xi);
    Vec2 xp = Vec2::Zero();
    Mat2 J = Mat2::Zero();  // ∂x/∂ξ in the deformed element
    for (int a = 0; a < n; ++a) {
      xp += s.N(a) * x_.col(c[a]);
      J += x_.col(c[a]) * s.dN_dxi.row(a);
    }
    const double det = J.determinant();
    if (!(std::abs(det) > 0)) return Found::elsewhere;
    const Vec2 step = J.inverse() * (q - xp);
    xi += step;
    if (xi.cwiseAbs().maxCoeff() > kFarXi) return Found::elsewhere;
    if (step.norm() < kNewtonTolerance) {
      // The sides that ξ lies beyond: all of them on the free edge or the grip means outside the
      // specimen (its deformed edge does not fold back over itself); an inner side, another element.
      const unsigned beyond = (xi(1) < -1 - kXiTolerance) | (xi(0) > 1 + kXiTolerance) << 1 |
                              (xi(1) > 1 + kXiTolerance) << 2 | (xi(0) < -1 - kXiTolerance) << 3;
      if (beyond == 0) return Found::inside;
      return (beyond & ~unsigned(outer_sides_[e])) == 0 ? Found::beyond_outer_edge : Found::elsewhere;
    }
  }
  return Found::elsewhere;
}

std::optional<Vec2> FullSpecimen::quarter_material_point(const Vec2& q, fem::Location* hint) const {
  if (q(0) > reach_(0) || q(1) > reach_(1)) return std::nullopt;  // beside the free edge or beyond the grip
  fem::Location at;
  bool found = false;
  if (hint && hint->element >= 0) {
    Vec2 xi = hint->xi;
    switch (newton_in_element(hint->element, q, xi)) {
      case Found::inside:
        at = fem::Location{hint->element, xi.cwiseMax(-1).cwiseMin(1)};
        found = true;
        break;
      case Found::beyond_outer_edge:
        return std::nullopt;  // background: no search of the mesh
      case Found::elsewhere:
        break;
    }
  }
  if (!found) {
    const auto located = current_.locate(q);
    if (!located) return std::nullopt;
    at = *located;
  }
  if (hint) *hint = at;
  return fem::interpolate(*mesh_, at, X_flat_);  // X(ξ) = Σ N_a(ξ) X_a
}

std::optional<Vec2> FullSpecimen::material_point(const Vec2& x, fem::Location* hint) const {
  const Vec2 sign = quadrant_signs(x);
  const auto X = quarter_material_point(x.cwiseAbs(), hint);
  if (!X) return std::nullopt;
  return Vec2(X->cwiseProduct(sign));
}

std::optional<Vec2> FullSpecimen::displacement(const Vec2& X) const {
  const Vec2 sign = quadrant_signs(X);
  const auto at = reference_.locate(X.cwiseAbs());
  if (!at) return std::nullopt;
  if (u_.size() == 0) return Vec2::Zero();
  return Vec2(fem::interpolate(*mesh_, *at, u_).cwiseProduct(sign));  // u(−X, Y) = (−u_X, u_Y)(X, Y), ...
}

// ---------------------------------------------------------------------------------------------------
// SpecimenRenderer

namespace {

// The pattern covers the whole reference specimen in reference-image px, so that any material point
// that comes into view, in any frame, has its own speckle.
SpecklePattern make_pattern(const fem::Mesh& quarter, const SpecimenImageOptions& o) {
  o.validate();
  const double W = quarter.X.row(0).maxCoeff(), H = quarter.X.row(1).maxCoeff();
  const Vec2 top_left = o.camera.to_pixel(Vec2(-W, H)), bottom_right = o.camera.to_pixel(Vec2(W, -H));
  return SpecklePattern(o.speckle, top_left(0), top_left(1), bottom_right(0), bottom_right(1));
}

}  // namespace

SpecimenRenderer::SpecimenRenderer(const fem::Mesh& quarter, const SpecimenImageOptions& options)
    : mesh_(&quarter), options_(options), pattern_(make_pattern(quarter, options)) {}

image::Image SpecimenRenderer::render(const Eigen::VectorXd& u, std::uint64_t noise_seed) const {
  const FullSpecimen body(*mesh_, u);
  const Camera& cam = options_.camera;
  const int s = options_.speckle.subsamples;
  const double background = options_.background;
  image::Image img(cam.width, cam.height, 0.0f, 1.0);
  const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();

  // A row is rendered from the centre column outward, each half starting from the centre's elements,
  // with one hint per row of sub-samples: Newton then starts in the element of the previous sub-sample
  // on the same line, and the background beside the specimen is recognised beyond the free edge of
  // the last element found (no search of the mesh).
  using Hints = std::array<fem::Location, 16>;
  const int c0 = std::clamp(static_cast<int>(std::lround(cam.centre_px()(0))), 0, cam.width - 1);
  const auto pixel = [&](int x, int y, Hints& hints) {
    double sum = 0;
    for (int b = 0; b < s; ++b)
      for (int a = 0; a < s; ++a) {
        // sub-sample centres of the pixel square [x − ½, x + ½] × [y − ½, y + ½], as synth::render
        const Vec2 xs(x - 0.5 + (a + 0.5) / s, y - 0.5 + (b + 0.5) / s);
        const auto X = body.material_point(cam.to_specimen(xs), &hints[b]);
        sum += X ? pattern_.intensity(cam.to_pixel(*X)) : background;
      }
    img.at(x, y) = static_cast<float>(sum / (s * s));
  };
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
  for (int y = 0; y < cam.height; ++y) {
    Hints right;
    pixel(c0, y, right);
    Hints left = right;
    for (int x = c0 + 1; x < cam.width; ++x) pixel(x, y, right);
    for (int x = c0 - 1; x >= 0; --x) pixel(x, y, left);
  }

  const double levels = options_.bits == 32 ? 1.0 : std::ldexp(1.0, options_.bits) - 1;
  if (options_.noise > 0) img = add_noise(img, options_.noise / levels, noise_seed);
  if (options_.bits != 32) {
    for (float& p : img.pixels) p = static_cast<float>(std::clamp(std::round(p * levels), 0.0, levels));
    img.full_scale = levels;
  }
  return img;
}

}  // namespace tricot::synth
