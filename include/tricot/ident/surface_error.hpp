// The paper's error measure, eq. (9) (docs/theory.md §9, paper §4.3.2): the mean relative distance between
// an identified response surface and the experimental forces per unit width, over the whole strain
// range and over the strains of practical use.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "tricot/fem/model.hpp"
#include "tricot/ident/experiment.hpp"

namespace tricot::ident {

/// A rectangle of material-frame Green–Lagrange strains (εC, εW), bounds included.
struct StrainDomain {
  double eC_min = 0.6, eC_max = 1.0;  ///< course (the paper's practical range: 60–100 %)
  double eW_min = 0.2, eW_max = 0.4;  ///< wale (20–40 %)

  bool contains(double eC, double eW) const { return eC >= eC_min && eC <= eC_max && eW >= eW_min && eW <= eW_max; }
  /// InputError naming `eq9.practical.<field>` for a non-finite bound or min > max.
  void validate() const;
};

/// One experimental point of a surface (docs/theory.md §9 [choice]): a step of a test pulled along that
/// direction, its grip force per unit initial width [N/mm] against the strains at the specimen centre.
struct SurfacePoint {
  double eC = 0, eW = 0;
  double force = 0;
  /// The centre strain across the pull at its test's first step (εW of a course pull, εC of a wale
  /// pull): the transverse level the test probes the surface at; NaN when unknown.
  double held = std::numeric_limits<double>::quiet_NaN();
};

/// How many transverse levels `points` probe their surface at: their `held` strains (NaN left out)
/// grouped where consecutive sorted values lie within `tolerance` of each other. One level is a
/// single path through the (εC, εW) plane (uniaxial tests, whatever their repeats): eq. 9 is then a
/// curve's error, not the surface's (docs/theory.md §9 [choice]).
int held_levels(const std::vector<SurfacePoint>& points, double tolerance = 0.05);

struct Eq9Error {
  double whole = std::numeric_limits<double>::quiet_NaN();      ///< ē over every point
  double practical = std::numeric_limits<double>::quiet_NaN();  ///< ē over the points in the domain
  int points_whole = 0, points_practical = 0;                   ///< N of each (points with F^exp = 0 left out)
};

/// ē = (1/N) Σ_i |F^id(εC_i, εW_i) − F_i^exp| / |F_i^exp| over `points` (those with F^exp = 0 are left
/// out: the relative distance is undefined there), and over those inside `practical`. Throws
/// InputError (key `eq9.practical`, naming the domain and the data's strain range) when the practical
/// domain holds no point, and (key `eq9.points`) when no point has a non-zero force.
Eq9Error eq9_error(const std::vector<SurfacePoint>& points, const std::function<double(double, double)>& identified,
                   const StrainDomain& practical = {});

/// Which surface a test's points belong to: the force its grip measures (docs/theory.md §9 [choice]).
enum class SurfaceForce { course, wale };

/// The eq. 9 points of one measured test (docs/theory.md §9 [choice]), or nullopt when the test gives none:
/// a material angle other than 0 (wale pulled, along y) or 90 (course pulled) [± 1e-9°], no grip
/// force, or no cumulative field of ≥ 3 points. Per step: force = edge_force / (2 × the quarter
/// mesh's width) [N/mm], and (εC, εW) at the specimen centre X = (0, 0) from the Green–Lagrange strain
/// of an affine fit u = a + G X of the measured displacements at the `nearest` field points closest
/// to the centre (all points if fewer).
struct TestSurfacePoints {
  SurfaceForce force = SurfaceForce::wale;
  std::vector<SurfacePoint> points;  ///< one per step
};
std::optional<TestSurfacePoints> test_surface_points(const fem::TestModel& model, const TestData& data,
                                                     int nearest = 6);

}  // namespace tricot::ident

namespace tricot::ident {

/// The identification on a restricted strain domain (paper §4.3.2: "identification of the surface
/// response on a more restrained experimental domain"; docs/theory.md §9 [choice]). From each test's centre
/// strains (test_surface_points, `nearest` points): a test is kept when its held strain — across the
/// pull, at its first step — lies in the domain's interval for that direction; its steps are kept up
/// to the last whose pulled strain is ≤ the domain's upper bound for the pulled direction (the steps
/// below the lower bound stay: the FE path goes through them). The later steps are neither simulated
/// nor compared.
struct RestrictedTest {
  std::string name;
  int steps = 0;      ///< in the data
  int kept = 0;       ///< 0: the test is left out
  double held = 0;    ///< the centre strain across the pull at the first step
  double pulled = 0;  ///< the pulled centre strain at the last kept step (at the first when none)
};
struct Restriction {
  std::vector<fem::TestModel> models;  ///< the kept tests, their loads cut
  Experiment experiment;               ///< their data, cut at the same step
  std::vector<RestrictedTest> tests;   ///< every test, in the experiment's order
};
/// Throws InputError, key `data.domain`, for a test without centre strains (see
/// test_surface_points) and when no test is kept. models[i] belongs to experiment.tests[i].
Restriction restrict_to_domain(const std::vector<fem::TestModel>& models, const Experiment& experiment,
                               const StrainDomain& domain, int nearest = 6);

}  // namespace tricot::ident
