// The project file of `tricot identify` as a typed spec: the case ([mesh], [law], [solver], [rig],
// [[test]]) with [experiment], [[parameter]], [data], [identify] and [eq9]; each field is named by its
// TOML key. read_identification_spec() reads it from a file validated by identify_schema(); a spec
// may also be built in code. IdentificationSpec::validate() is its one check; the checks that
// need the measurements (the experiment folder, truth.json, field.csv's columns, eq. 9's domain
// against the data) are made by build_project() (identification.hpp), which reads them.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tricot/ident/experiment.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/stability_barrier.hpp"
#include "tricot/ident/surface_error.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// The project file: the case sections ([mesh], [law], [solver], [[test]]) with [experiment],
/// [[parameter]], [data], [identify] and [eq9].
io::SectionSpec identify_schema();

/// [identify]: Levenberg–Marquardt and its stopping criteria. The engines' keys are held as the engines
/// take them, each declared once by the options that hold it (core/options.hpp): ident::IdentifyOptions's,
/// and ident::ObjectiveOptions's warm_start; coarse_mesh is the verb's.
struct IdentifyTable {
  ident::IdentifyOptions lm;  ///< as ident::identify takes them (options() checks them)
  /// warm_start; build_project completes the objective's options ([data], [solver], lm.threads).
  ident::ObjectiveOptions objective;
  /// [nx, ny]: identify by mesh levels, every test first on nx × ny elements (ident::identify_by_levels);
  /// empty: on the project's meshes alone.
  io::Reals coarse_mesh;
  Origin origin{"identify"};

  static auto keys() {
    using O = IdentifyTable;
    return std::tuple{
        option(&O::coarse_mesh, "identify.coarse_mesh",
               "[nx, ny]: identify by mesh levels. LM (with the stability test) first runs on every test meshed\n"
               "with nx × ny elements ([mesh]'s other keys; a test's own nx, ny give way), then the project's\n"
               "meshes are solved through that coarse model corrected to them at each point (space mapping:\n"
               "one fine evaluation a step). For large meshes: the paper's 24 874-dof identification takes\n"
               "45–48 s with [12, 10] against 323 s on the fine mesh alone. Not with --resume. [] = off.",
               1, 10000)};
  }
  /// From the [identify] table of a file read with identify_schema().
  static IdentifyTable from_config(const io::Node& table);
  /// The engine's options, validated: an error names its key at its origin.
  ident::IdentifyOptions options() const;
};

/// [experiment] of a project file: the measurements' folder and their σ.
struct ProjectExperimentSpec {
  std::string dir = "experiment";         ///< relative to the project file's folder
  std::string field_kind = "cumulative";  ///< cumulative or incremental
  double sigma_edge_displacement = 0;     ///< mm, ≥ 0; 0 = unknown
  double sigma_edge_force = 0;            ///< N, ≥ 0; 0 = unknown
  double sigma_field = 0;                 ///< mm, ≥ 0; 0 = unknown
  bool sigma_from_truth = false;          ///< σ of every test from DIR/truth.json
  Origin origin{"experiment"};

  static ProjectExperimentSpec from_config(const io::Node& table);
  ident::FieldKind kind() const;  ///< field_kind (validated)
};

/// [[parameter]]: one identified coefficient of [law].
struct ParameterSpec {
  std::string name = "C10";
  std::optional<double> start;  ///< unset: the coefficient's [law] value
  double scale = 0;             ///< ≥ 0; 0 = |start|
  io::Reals bounds;             ///< [] or [lower, upper]
  Origin origin{"parameter"};

  static ParameterSpec from_config(const io::Node& table);
};

/// [data]: the weights of the data groups (ident::DataWeights) and the field's σ.
struct DataSpec {
  double edge_displacement = ident::DataWeights{}.edge_displacement;
  double edge_force = ident::DataWeights{}.edge_force;
  double field = ident::DataWeights{}.field;
  bool field_uv = ident::DataWeights{}.field_uv;
  std::string field_sigma = "group";  ///< group or per_point
  std::string weighting = "scaled";   ///< scaled (eq. 1) or fixed (ident::DataWeights::fixed)
  /// [min, max] εC and εW of a domain-restricted identification (ident::restrict_to_domain); both
  /// unset: every step of every test. One unset: that direction is not restricted.
  std::optional<io::Reals> domain_course, domain_wale;
  /// 0: the steps outside the domain are left out (the restriction); in (0, 1]: every step is kept and
  /// those outside weigh this much (TestData::step_weight; paper §4.3.2 "weighted").
  double domain_weight = 0;
  Origin origin{"data"};

  static DataSpec from_config(const io::Node& table);
  /// The restriction's domain (validated), or nullopt when neither key is given.
  std::optional<ident::StrainDomain> domain() const;
};

/// [eq9]: the practical domain and the centre-strain fit of eq. 9 (docs/theory.md §9).
struct Eq9Spec {
  /// [min, max] εC and εW; unset: ident::StrainDomain's default (which may miss the data: then
  /// result.json's "practical" is null), set: it must hold some of the data's points.
  std::optional<io::Reals> practical_course, practical_wale;
  int nearest = 6;  ///< ≥ 3
  /// Eq. 9 of a surface is computed when its points probe it at this many transverse levels or more
  /// (ident::held_levels), ≥ 1; below: "not computed" with the counts.
  int min_held_levels = 2;
  Origin origin{"eq9"};

  static Eq9Spec from_config(const io::Node& table);
  ident::StrainDomain practical() const;  ///< the domain (validated)
};

/// [design]: the next test to run (beyond the paper; ident::suggest_test): for each pull of the rig
/// tests, the first such test held at each candidate transverse strain, ranked by the criterion.
struct DesignSpec {
  io::Reals transverse_strains;         ///< the candidate held strains (Green–Lagrange)
  std::string criterion = "d_optimal";  ///< d_optimal or a_optimal
  Origin origin{"design"};
};

/// The whole project file. The case's tables are the base's fields (mesh, law, solver, rig, test).
struct IdentificationSpec : CaseSpec {
  ProjectExperimentSpec experiment;
  std::vector<ParameterSpec> parameter;
  DataSpec data;
  IdentifyTable identify;
  Eq9Spec eq9;
  /// [identifiability]: result.json's identifiability report (ident/identifiability.hpp; sigma2 is the run's).
  ident::IdentifiabilityOptions identifiability;
  /// [stability] enabled: the material-stability barrier's options (ident/stability_barrier.hpp).
  std::optional<ident::StabilityBarrierOptions> stability;
  /// Where [identifiability] and [stability] came from: their engines name the keys, these place them.
  Origin identifiability_origin{"identifiability"}, stability_origin{"stability"};
  /// [design] with transverse_strains: result.json's "design".
  std::optional<DesignSpec> design;
  /// The project file ("" when built in code): errors of the objective name it; the report shows it.
  std::filesystem::path file;

  /// The one check of the spec (the case's tests and models, the law and its coefficients, the
  /// parameters against the law, [identify], [identifiability], [stability], and the words and ranges
  /// of [experiment], [data] and [eq9]). Throws InputError naming the key (FILE:LINE: KEY for a spec
  /// read from a file).
  void validate() const;
};

/// The spec of a project file validated by identify_schema() (types and ranges checked there).
IdentificationSpec read_identification_spec(const io::Node& root);
/// A [[test]] without loads, load_max or steps takes its loads from its forces.csv in the experiment
/// folder (relative to `base`, the project file's folder), when there is one (issue 29): the lab's
/// loads are written once, in the experiment.
void read_loads_from_experiment(IdentificationSpec& spec, const std::filesystem::path& base);

}  // namespace tricot::project
