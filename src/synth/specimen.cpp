// Synthetic images of the deformed full specimen (see specimen.hpp).
#include "tricot/synth/specimen.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <string>

#include <Eigen/QR>

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
    : mesh_(&quarter), u_(u), X_flat_(Eigen::Map<const Eigen::VectorXd>(quarter.X.data(), quarter.dofs())),
      x_(quarter.X), current_(quarter, u.size() ? &u_ : nullptr), reference_(quarter) {
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
      case Found::beyond_outer_edge: return std::nullopt;  // background: no search of the mesh
      case Found::elsewhere: break;
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

// The reference specimen [−W, W] × [−H, H] in reference-image px: the pattern covers it, so that any
// material point that comes into view, in any frame, has its own speckle.
struct PixelBox {
  Vec2 top_left, bottom_right;
};
PixelBox specimen_box(const fem::Mesh& mesh, Extent extent, const SpecimenImageOptions& o) {
  o.validate();
  const Vec2 hi = mesh.X.rowwise().maxCoeff();
  const Vec2 lo = extent == Extent::quarter ? Vec2(-hi) : Vec2(mesh.X.rowwise().minCoeff());
  return {o.camera.to_pixel(Vec2(lo(0), hi(1))), o.camera.to_pixel(Vec2(hi(0), lo(1)))};
}
// The pattern's table covers the reference specimen within twice the camera's view about its centre:
// what a frame shows unless the specimen shrinks to less than half its size across the view. A
// material point off the table is the pattern's own intensity (slower, the same image).
PatternTable::Box table_box(const fem::Mesh& mesh, Extent extent, const SpecimenImageOptions& o) {
  const PixelBox b = specimen_box(mesh, extent, o);
  const Camera& c = o.camera;
  const Vec2 lo = b.top_left.cwiseMax(c.centre_px() - Vec2(c.width, c.height));
  const Vec2 hi = b.bottom_right.cwiseMin(c.centre_px() + Vec2(c.width, c.height));
  return {lo, hi.cwiseMax(lo)};
}
SpecklePattern make_pattern(const fem::Mesh& mesh, Extent extent, const SpecimenImageOptions& o) {
  const PixelBox b = specimen_box(mesh, extent, o);
  return SpecklePattern(o.speckle, b.top_left(0), b.top_left(1), b.bottom_right(0), b.bottom_right(1));
}

// The serendipity monomials m(ξ) = (1, ξ₁, ξ₂, ξ₁², ξ₁ξ₂, ξ₂², ξ₁²ξ₂, ξ₁ξ₂²): the shape functions of
// every element type (Q4, Q8 and, with their first three or six, T3, T6) are combinations of them,
// N(ξ) = B m(ξ), so an element's map Σ N_a(ξ) x_a is C m(ξ) with C = [x_a] B, 2 × 8 numbers per element
// evaluated without a shape-function call.
using Monomials = Eigen::Matrix<double, 8, 1>;
Monomials monomials(const Vec2& xi) {
  const double s = xi(0), t = xi(1);
  Monomials m;
  m << 1, s, t, s * s, s * t, t * t, s * s * t, s * t * t;
  return m;
}
// B (node a, monomial k) from fem::shape at the 3 × 3 points ξ ∈ {−1, 0, 1}², where the eight
// monomials are independent: the least-squares fit is exact for any shape functions they span.
Eigen::Matrix<double, 8, 8> shape_in_monomials(fem::ElementType type) {
  Eigen::Matrix<double, 9, 8> V, N;
  for (int p = 0; p < 9; ++p) {
    const Vec2 xi(p % 3 - 1, p / 3 - 1);
    V.row(p) = monomials(xi).transpose();
    N.row(p) = fem::shape(type, xi).N.transpose();
  }
  return V.colPivHouseholderQr().solve(N).transpose();
}

// Newton on the inverse map stops once a step is below this: the error left is then of order
// |J⁻¹ ∂²x/∂ξ²| · step² ≲ 1e-6 of an element, 1e-5 px on a 20 px element, which moves a gray level by
// ~1e-5 of the speckle's contrast. From the row's predictor (the last inverse Jacobian times the step
// between sub-samples) one iteration meets it.
constexpr double kInverseStep = 1e-3;
constexpr int kInverseIterations = 20;
// Pixel rows per band: a band's sub-samples (width · s × 8 s floats) stay in cache while its
// elements are drawn, and bands are the unit of parallel work.
constexpr int kBandRows = 8;
// Anchors of Newton's solution along a row are this far apart (px); the cubic Hermite interpolant of
// xi(x) between two is off by about spacing^4/384 times its fourth derivative: below 1e-6 of an
// element for 2 px on elements of 10 px and more (specimen_test's OldRenderer tests).
constexpr double kAnchorSpacing = 2.0;
// Elements' bounding boxes are widened by this (px), far above the round-off of their bounds.
constexpr double kBoxMargin = 1e-6;

// One element of the specimen (of the quarter, mirrored into one quadrant of the full specimen), in
// image px: its current position x(ξ) = Σ_k cx_k m_k(ξ) (and y), its material point in reference-image
// px (the pattern's coordinates) P(ξ) = Σ_k P_k m_k(ξ), and the bounds of x over the element. Scalar
// code: the inner loop of the renderer, one call per sub-sample.
struct Patch {
  std::array<double, 8> cx, cy, Px, Py;
  Vec2 lo, hi;
  bool triangle = false;  ///< ξ on the triangle ξ₁, ξ₂ ≥ 0, ξ₁ + ξ₂ ≤ 1, else on [−1, 1]²

  // ξ lies on the element, to kXiTolerance.
  bool holds(double s, double t) const {
    if (triangle) return s >= -kXiTolerance && t >= -kXiTolerance && s + t <= 1 + kXiTolerance;
    return std::max(std::abs(s), std::abs(t)) <= 1 + kXiTolerance;
  }
  // Where Newton starts without a neighbour's ξ: the element's centre.
  double centre() const { return triangle ? 1.0 / 3 : 0.0; }

  static double dot(const std::array<double, 8>& c, double s, double t, double ss, double st, double tt) {
    return c[0] + c[1] * s + c[2] * t + c[3] * ss + c[4] * st + c[5] * tt + c[6] * ss * t + c[7] * s * tt;
  }
  // Newton on x(ξ) = q from ξ = (s, t); J_inv (row-major 2 × 2) is left at the last iterate's inverse
  // Jacobian. False when the map is singular or ξ runs beyond the extrapolation trusted (kFarXi).
  bool invert(double qx, double qy, double& s, double& t, std::array<double, 4>& J_inv) const {
    for (int it = 0; it < kInverseIterations; ++it) {
      const double ss = s * s, st = s * t, tt = t * t;
      const double rx = qx - dot(cx, s, t, ss, st, tt), ry = qy - dot(cy, s, t, ss, st, tt);
      // ∂m/∂s = (0, 1, 0, 2s, t, 0, 2st, t²), ∂m/∂t = (0, 0, 1, 0, s, 2t, s², 2st)
      const double xs = cx[1] + 2 * cx[3] * s + cx[4] * t + 2 * cx[6] * st + cx[7] * tt;
      const double xt = cx[2] + cx[4] * s + 2 * cx[5] * t + cx[6] * ss + 2 * cx[7] * st;
      const double ys = cy[1] + 2 * cy[3] * s + cy[4] * t + 2 * cy[6] * st + cy[7] * tt;
      const double yt = cy[2] + cy[4] * s + 2 * cy[5] * t + cy[6] * ss + 2 * cy[7] * st;
      const double det = xs * yt - xt * ys;
      if (!(std::abs(det) > 0)) return false;
      const double inv = 1 / det;
      J_inv = {yt * inv, -xt * inv, -ys * inv, xs * inv};
      const double ds = J_inv[0] * rx + J_inv[1] * ry, dt = J_inv[2] * rx + J_inv[3] * ry;
      s += ds, t += dt;
      if (std::max(std::abs(s), std::abs(t)) > kFarXi) return false;
      if (std::max(std::abs(ds), std::abs(dt)) < kInverseStep) return true;
    }
    return false;
  }
  // (dx/dxi)^-1 at xi = (s, t), row-major; zero where the map is singular.
  std::array<double, 4> inverse_jacobian(double s, double t) const {
    const double ss = s * s, st = s * t, tt = t * t;
    const double xs = cx[1] + 2 * cx[3] * s + cx[4] * t + 2 * cx[6] * st + cx[7] * tt;
    const double xt = cx[2] + cx[4] * s + 2 * cx[5] * t + cx[6] * ss + 2 * cx[7] * st;
    const double ys = cy[1] + 2 * cy[3] * s + cy[4] * t + 2 * cy[6] * st + cy[7] * tt;
    const double yt = cy[2] + cy[4] * s + 2 * cy[5] * t + cy[6] * ss + 2 * cy[7] * st;
    const double det = xs * yt - xt * ys;
    if (!(std::abs(det) > 0)) return {};
    return {yt / det, -xt / det, -ys / det, xs / det};
  }
  Vec2 material(double s, double t) const {
    const double ss = s * s, st = s * t, tt = t * t;
    return {dot(Px, s, t, ss, st, tt), dot(Py, s, t, ss, st, tt)};
  }
};

// The full specimen's elements in image px: the mesh's own, or the quarter's 4 mirror images.
std::vector<Patch> patches(const fem::Mesh& mesh, Extent extent, const Eigen::VectorXd& u, const Camera& cam) {
  const Eigen::Matrix<double, 8, 8> B = shape_in_monomials(mesh.type);
  const int n = fem::nodes_per_element(mesh.type), corners = fem::corners(mesh.type);
  const bool quadratic = n > corners;
  const bool triangle = corners == 3;
  std::vector<Vec2> signs{Vec2(1, 1)};
  if (extent == Extent::quarter) signs = {Vec2(1, 1), Vec2(-1, 1), Vec2(1, -1), Vec2(-1, -1)};
  std::vector<Patch> out;
  out.reserve(signs.size() * std::size_t(mesh.elements()));
  for (const Vec2& sign : signs)
    for (int e = 0; e < mesh.elements(); ++e) {
      const auto& c = mesh.connectivity[e];
      Eigen::Matrix<double, 2, 8> x = Eigen::Matrix<double, 2, 8>::Zero(), P = x;
      for (int a = 0; a < n; ++a) {
        const Vec2 X = mesh.X.col(c[a]);
        const Vec2 xa = u.size() ? Vec2(X + u.segment<2>(2 * c[a])) : X;
        x.col(a) = cam.to_pixel(xa.cwiseProduct(sign));
        P.col(a) = cam.to_pixel(X.cwiseProduct(sign));
      }
      const Eigen::Matrix<double, 2, 8> Cx = x * B, CP = P * B;
      Patch p;
      p.triangle = triangle;
      for (int k = 0; k < 8; ++k) p.cx[k] = Cx(0, k), p.cy[k] = Cx(1, k), p.Px[k] = CP(0, k), p.Py[k] = CP(1, k);
      p.lo = x.leftCols(n).rowwise().minCoeff();
      p.hi = x.leftCols(n).rowwise().maxCoeff();
      // A quadratic side is a parabola through its end and mid-side nodes: it passes them by ≤ |x_a − 2x_m + x_b|/8.
      if (quadratic)
        for (int k = 0; k < corners; ++k) {
          const int a = k, b = (k + 1) % corners, m = corners + k;
          const Vec2 bulge = (x.col(a) - 2 * x.col(m) + x.col(b)).cwiseAbs() / 8;
          p.lo = p.lo.cwiseMin(x.col(a).cwiseMin(x.col(b)).cwiseMin(x.col(m)) - bulge);
          p.hi = p.hi.cwiseMax(x.col(a).cwiseMax(x.col(b)).cwiseMax(x.col(m)) + bulge);
        }
      // A sub-sample on a side shared by two elements must fall in both boxes despite round-off.
      p.lo.array() -= kBoxMargin;
      p.hi.array() += kBoxMargin;
      out.push_back(p);
    }
  return out;
}

}  // namespace

SpecimenRenderer::SpecimenRenderer(const fem::Mesh& mesh, const SpecimenImageOptions& options, Extent extent)
    : mesh_(&mesh), extent_(extent), options_(options), pattern_(make_pattern(mesh, extent, options)),
      table_(pattern_, table_box(mesh, extent, options)) {}

image::Image SpecimenRenderer::render(const Eigen::VectorXd& u, std::uint64_t noise_seed) const {
  assert(u.size() == 0 || u.size() == mesh_->dofs());
  const Camera& cam = options_.camera;
  const int s = options_.speckle.subsamples;
  const double sub = 1.0 / s;
  const float background = static_cast<float>(options_.background);
  image::Image img(cam.width, cam.height, 0.0f, 1.0);
  const int threads = options_.threads > 0 ? options_.threads : omp_get_max_threads();
  const std::vector<Patch> elements = patches(*mesh_, extent_, u, cam);

  // Sub-sample (i, j) lies at x = (i + ½)/s − ½, y = (j + ½)/s − ½ px: pixel (⌊i/s⌋, ⌊j/s⌋)'s sub-sample
  // centres, as synth::render. Each element draws the sub-samples of its bounding box that it holds
  // (Patch::holds, to kXiTolerance), walking each row with Newton from the previous sub-sample's ξ
  // moved by the last inverse Jacobian; sub-samples no element holds show the flat background. A
  // sub-sample on a side two elements share gets the same material point from either.
  const int row_samples = cam.width * s;
  const auto first_sample = [&](double x) { return static_cast<int>(std::ceil(s * (x + 0.5) - 0.5)); };
  const auto last_sample = [&](double x) { return static_cast<int>(std::floor(s * (x + 0.5) - 0.5)); };
  const auto draw = [&](const Patch& p, int j_begin, int j_end, float* band) {
    const int i0 = std::max(0, first_sample(p.lo(0))), i1 = std::min(row_samples - 1, last_sample(p.hi(0)));
    const int j0 = std::max(j_begin, first_sample(p.lo(1))), j1 = std::min(j_end - 1, last_sample(p.hi(1)));
    // Along a row, Newton solves ξ exactly at anchors every `stride` sub-samples (from the previous
    // anchor's ξ moved by its inverse Jacobian), and the sub-samples between two anchors take the
    // cubic Hermite interpolant of ξ(x) through the anchors' ξ and dξ/dx (kAnchorSpacing). Where an
    // anchor has no ξ (the map is singular there, or it lies far beyond the element), the sub-samples
    // around it are solved one by one.
    const int stride = std::max(1, static_cast<int>(std::lround(kAnchorSpacing * s)));
    double s_row = 0, t_row = 0, y_row = 0;
    std::array<double, 4> J_inv_row{};
    const auto solve = [&p](double x, double y, double& xi_s, double& xi_t, std::array<double, 4>& J_inv) {
      if (p.invert(x, y, xi_s, xi_t, J_inv)) return true;
      xi_s = xi_t = p.centre();
      if (p.invert(x, y, xi_s, xi_t, J_inv)) return true;
      xi_s = xi_t = 0, J_inv = {};
      return false;
    };
    const auto shade = [&](float* out, int i, double xi_s, double xi_t) {
      if (p.holds(xi_s, xi_t)) out[i] = static_cast<float>(table_.intensity(p.material(xi_s, xi_t)));
    };
    for (int j = j0; j <= j1; ++j) {
      const double y = (j + 0.5) * sub - 0.5;
      float* out = band + std::size_t(j - j_begin) * row_samples;
      // The first anchor from the row above's.
      double as = s_row + J_inv_row[1] * (y - y_row), at = t_row + J_inv_row[3] * (y - y_row);
      std::array<double, 4> J_inv{};
      double ax = (i0 + 0.5) * sub - 0.5;
      bool a_ok = solve(ax, y, as, at, J_inv);
      std::array<double, 2> a_d{};
      if (a_ok) {
        J_inv = p.inverse_jacobian(as, at);
        a_d = {J_inv[0], J_inv[2]};
        s_row = as, t_row = at, J_inv_row = J_inv, y_row = y;
        shade(out, i0, as, at);
      }
      for (int ia = i0; ia < i1;) {
        const int ib = std::min(i1, ia + stride);
        const double bx = (ib + 0.5) * sub - 0.5, h = bx - ax;
        double bs = as + J_inv[0] * h, bt = at + J_inv[2] * h;  // the predictor (J_inv zero after a failure)
        const bool b_ok = solve(bx, y, bs, bt, J_inv);
        std::array<double, 2> b_d{};
        if (b_ok) {
          J_inv = p.inverse_jacobian(bs, bt);
          b_d = {J_inv[0], J_inv[2]};
        }
        if (a_ok && b_ok) {
          for (int i = ia + 1; i < ib; ++i) {
            // Hermite basis on u ∈ (0, 1): h00 = (1 + 2u)(1 − u)², h10 = u(1 − u)², h01 = u²(3 − 2u), h11 = u²(u − 1)
            const double u = double(i - ia) / (ib - ia), v = 1 - u;
            const double h00 = (1 + 2 * u) * v * v, h10 = u * v * v * h, h01 = u * u * (3 - 2 * u),
                         h11 = u * u * (u - 1) * h;
            shade(out, i, h00 * as + h10 * a_d[0] + h01 * bs + h11 * b_d[0],
                  h00 * at + h10 * a_d[1] + h01 * bt + h11 * b_d[1]);
          }
        } else {
          double xs = a_ok ? as : 0, xt = a_ok ? at : 0;
          std::array<double, 4> J = a_ok ? p.inverse_jacobian(as, at) : std::array<double, 4>{};
          for (int i = ia + 1; i < ib; ++i) {
            xs += J[0] * sub, xt += J[2] * sub;
            if (solve((i + 0.5) * sub - 0.5, y, xs, xt, J)) shade(out, i, xs, xt);
          }
        }
        if (b_ok) shade(out, ib, bs, bt);
        ia = ib, ax = bx, as = bs, at = bt, a_ok = b_ok, a_d = b_d;
      }
    }
  };

  const int bands = (cam.height + kBandRows - 1) / kBandRows;
#pragma omp parallel num_threads(threads)
  {
    std::vector<float> band(std::size_t(row_samples) * kBandRows * s);
#pragma omp for schedule(dynamic, 1)
    for (int b = 0; b < bands; ++b) {
      const int y_begin = b * kBandRows, y_end = std::min(cam.height, y_begin + kBandRows);
      const int j_begin = y_begin * s, j_end = y_end * s;
      std::fill(band.begin(), band.end(), background);
      const double top = (j_begin + 0.5) * sub - 0.5, bottom = (j_end - 0.5) * sub - 0.5;  // sub-sample rows' y
      for (const Patch& p : elements)
        if (p.hi(1) >= top && p.lo(1) <= bottom && p.hi(0) >= -0.5 && p.lo(0) <= cam.width - 0.5)
          draw(p, j_begin, j_end, band.data());
      // Each pixel: the mean of its s × s sub-samples.
      for (int y = y_begin; y < y_end; ++y)
        for (int x = 0; x < cam.width; ++x) {
          double sum = 0;
          for (int b2 = 0; b2 < s; ++b2) {
            const float* r = band.data() + std::size_t((y - y_begin) * s + b2) * row_samples + std::size_t(x) * s;
            for (int a = 0; a < s; ++a) sum += r[a];
          }
          img.at(x, y) = static_cast<float>(sum / (s * s));
        }
    }
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
