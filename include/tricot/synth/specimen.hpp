// Synthetic camera images of a deformed specimen (docs/design.md, paper §3.1.3): the camera on its
// pantograph aims at the specimen centre, which stays at the image centre; the fabric's roughness is
// the speckle. The FE model is either the whole specimen (any mesh: the camera sees the mesh frame's
// origin at the image centre) or the quarter X ≥ 0, Y ≥ 0 with symmetry, whose full specimen's
// displacement is the quarter's mirrored: u(−X, Y) = (−u_X, u_Y)(X, Y), u(X, −Y) = (u_X, −u_Y)(X, Y).
//
// A pixel at current position x sees the material point X with X + u(X) = x: x is mirrored into the
// first quadrant, located in the DEFORMED quarter mesh (fem::PointLocator with u), mapped back to X by
// the element's shape functions and mirrored back; the pixel then shows the continuous speckle
// pattern (speckle.hpp) at X, so the pattern is not symmetric and nothing is ever warped. Outside the
// specimen (beside it, beyond the grips) the image is a flat gray.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "tricot/core/types.hpp"
#include "tricot/fem/locate.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/image/image.hpp"
#include "tricot/synth/speckle.hpp"

namespace tricot::synth {

/// The camera: square pixels, the specimen centre at the image centre, no rotation. Specimen axes:
/// X to the right, Y UP (image y points down), so that X = s · (x − c_x), Y = −s · (y − c_y) with
/// c = ((width − 1)/2, (height − 1)/2) (pixel centres are at integer coordinates). This is
/// dic::PhysicalFrame{mm_per_px, c, angle_deg = 0, y_up = true}, the default of `tricot dic`'s [physical].
struct Camera {
  double mm_per_px = 0.1;  ///< pixel size in mm on the specimen, > 0
  int width = 600;         ///< image width in px, 8–20000
  int height = 600;        ///< image height in px, 8–20000

  /// Throws InputError naming `camera.<field>` when out of range.
  void validate() const;
  /// The specimen-centre pixel c (the image centre).
  Vec2 centre_px() const { return {0.5 * (width - 1), 0.5 * (height - 1)}; }
  /// A pixel position → specimen coordinates, mm.
  Vec2 to_specimen(const Vec2& x_px) const {
    return {mm_per_px * (x_px(0) - centre_px()(0)), -mm_per_px * (x_px(1) - centre_px()(1))};
  }
  /// Specimen coordinates, mm → pixel position.
  Vec2 to_pixel(const Vec2& X) const { return {centre_px()(0) + X(0) / mm_per_px, centre_px()(1) - X(1) / mm_per_px}; }
};

/// What the FE mesh is of the specimen the camera sees.
enum class Extent {
  quarter,  ///< the quarter X, Y ≥ 0 of a specimen symmetric about both axes (the built-in tests)
  whole,    ///< the whole specimen (any mesh: a test with named boundary conditions)
};

/// The full specimen [−W, W] × [−H, H] seen through its quarter model (W, H: the quarter mesh's size)
/// at one deformed state: the maps between material points X and current points x = X + u(X).
class FullSpecimen {
 public:
  /// `quarter`: the reference quarter mesh (it must outlive this object); `u`: its nodal
  /// displacements (2·nodes, copied), or empty for the unloaded specimen.
  FullSpecimen(const fem::Mesh& quarter, const Eigen::VectorXd& u);

  /// The material point X (mm) at the current point x (mm), or nullopt when x is outside the deformed
  /// specimen. `hint` (optional) is an element and ξ to try first (a neighbouring point's): Newton in
  /// that element; a point beyond one of its sides on the free edge or the grip is outside without a
  /// search (the deformed outline must not fold back over itself), any other the locator finds. The
  /// hint is updated to where x was found.
  std::optional<Vec2> material_point(const Vec2& x, fem::Location* hint = nullptr) const;
  /// The displacement u(X) (mm) of a material point X of the full specimen, or nullopt when X is
  /// outside the reference specimen.
  std::optional<Vec2> displacement(const Vec2& X) const;

 private:
  enum class Found { inside, beyond_outer_edge, elsewhere };
  // x mirrored into the quadrant, located in the deformed quarter; ξ → X by the shape functions.
  std::optional<Vec2> quarter_material_point(const Vec2& q, fem::Location* hint) const;
  // Newton on x(ξ) = q in element e from ξ: inside the element, beyond one of its sides on the
  // specimen's free edge or grip (so outside the specimen), or neither (ask the locator).
  Found newton_in_element(int e, const Vec2& q, Vec2& xi) const;

  const fem::Mesh* mesh_;
  std::vector<unsigned char> outer_sides_;  ///< per element, bit k: side k lies on the edge x = W or y = H
  Vec2 reach_ = Vec2::Zero();               ///< bounds on the deformed quarter's largest x and y
  Eigen::VectorXd u_;                       ///< the quarter's nodal displacements (empty = none)
  Eigen::VectorXd X_flat_;                  ///< reference node positions, 2 per node (the form fem::interpolate takes)
  Eigen::Matrix2Xd x_;                      ///< deformed node positions
  fem::PointLocator current_;               ///< in the deformed quarter
  fem::PointLocator reference_;
};

/// How the specimen images look and are stored.
struct SpecimenImageOptions {
  Camera camera;
  /// The fabric's speckle, in px of the reference image (radius = half the speckle size); `seed`
  /// fixes the pattern; `subsamples` per pixel and direction integrate each pixel's area, 1–16.
  SpeckleOptions speckle;
  double background = 0.5;  ///< flat gray outside the specimen, fraction of full scale, 0–1
  double noise = 0;         ///< σ of zero-mean Gaussian noise in gray levels of the output (8 bit: of 255), ≥ 0
  /// 8 or 16: gray levels rounded to integers, full_scale 2^bits − 1 (a camera's output);
  /// 32: float, full_scale 1, not quantised (for tests).
  int bits = 8;
  int threads = 0;  ///< OpenMP threads over rows, 0 = the OpenMP default

  /// Throws InputError naming `images.<field>` (or `speckle.<field>`) when out of range.
  void validate() const;
};

/// Renders the images of one specimen: the speckle pattern is made once (over the reference specimen,
/// so a material point keeps its gray level in every frame) and each call renders one deformed state.
class SpecimenRenderer {
 public:
  /// Validates `options` (InputError). `mesh` (any element type) must outlive the renderer; `extent`
  /// says whether it is the quarter of the specimen (mirrored into the four quadrants) or all of it.
  SpecimenRenderer(const fem::Mesh& mesh, const SpecimenImageOptions& options, Extent extent = Extent::quarter);

  /// The image of the specimen deformed by the mesh's nodal displacements `u` (2·nodes; empty =
  /// the unloaded reference). Each pixel is the mean over subsamples² points of its square of the
  /// speckle at their material points (the flat background where a point is off the specimen), plus
  /// noise drawn from `noise_seed` (independent of the thread count), then quantised to `bits`.
  /// The material points are found element by element: each deformed element (of the mesh, or of the
  /// quarter's four mirror images) draws the sub-samples of its bounding box that it holds, by Newton on its
  /// isoparametric map from the previous sub-sample's ξ; the speckle comes from table(). The same
  /// image as FullSpecimen::material_point and pattern().intensity per sub-sample, to the table's
  /// error (specimen_test's OldRenderer tests).
  image::Image render(const Eigen::VectorXd& u, std::uint64_t noise_seed = 0) const;

  /// The pattern, in reference-image px: the material point X shows pattern.intensity(camera.to_pixel(X)).
  const SpecklePattern& pattern() const { return pattern_; }
  /// The pattern tabulated over the reference specimen: what render() samples.
  const PatternTable& table() const { return table_; }
  const SpecimenImageOptions& options() const { return options_; }

 private:
  const fem::Mesh* mesh_;
  Extent extent_;
  SpecimenImageOptions options_;
  SpecklePattern pattern_;
  PatternTable table_;
};

}  // namespace tricot::synth
