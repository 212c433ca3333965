// tricot identify: the project file, the run (checkpoints, resume) and its outputs (result.json,
// history.csv, plots): the pipeline of `tricot identify`, which `tricot demo` runs too.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "tricot/project/log.hpp"
#include "tricot/project/experiment_files.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/identify.hpp"
#include "tricot/ident/identifiability.hpp"
#include "tricot/ident/stability_barrier.hpp"
#include "tricot/ident/objective.hpp"
#include "tricot/ident/surface_error.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/identification_spec.hpp"
#include "tricot/project/spec.hpp"

namespace tricot::project {

/// A project's model of its experiment, ready for ident::identify.
/// Eq. 9's points: [0] course, [1] wale.
using SurfacePoints = std::array<std::vector<ident::SurfacePoint>, 2>;

struct Project {
  std::unique_ptr<fem::Law> law;
  fem::SolveOptions solver;
  std::vector<fem::TestModel> models;
  ident::IdentifyOptions options;  ///< from [identify]
  std::optional<Truth> truth;      ///< the experiment's truth.json, when it has one
  std::unique_ptr<ident::Objective> objective;
  ident::ObjectiveOptions objective_options;  ///< the objective's ([data] weights, solver, threads)
  ident::StrainDomain eq9_practical;          ///< [eq9] practical_course, practical_wale
  int eq9_nearest = 6;                        ///< [eq9] nearest
  int eq9_min_held_levels = 2;                ///< [eq9] min_held_levels
  /// Eq. 9's experimental points of every test of the experiment (a restricted run included).
  SurfacePoints eq9_points;
  /// [data] domain_course, domain_wale given: what the restriction kept of each test (the models
  /// and the objective hold the kept tests only); empty otherwise.
  std::vector<ident::RestrictedTest> restriction;
  ident::IdentifiabilityOptions identifiability;  ///< [identifiability] (sigma2 from the run)
  /// [stability] enabled: the objective with the material-stability barrier; LM minimises it.
  std::unique_ptr<ident::StabilizedObjective> stability;
  /// [identify] coarse_mesh: the first level of an identification by mesh levels (the tests meshed
  /// coarse, their objective on the same data, with the barrier under [stability]); empty without.
  std::vector<fem::TestModel> coarse_models;
  std::unique_ptr<ident::Objective> coarse_objective;
  std::unique_ptr<ident::StabilizedObjective> coarse_stability;
};

/// Eq. 9's experimental points of tests and their data (docs/theory.md §9 [choice]): [0] course (tests with
/// material_angle 90), [1] wale (angle 0), one per step, from ident::test_surface_points.
SurfacePoints eq9_points(const std::vector<fem::TestModel>& models, const ident::Experiment& experiment, int nearest);
/// Checks the spec (its validate()), reads its experiment (relative to `base`) and builds its
/// objective. Throws InputError located at the spec's keys (FileError for a missing file or folder).
Project build_project(const IdentificationSpec& spec, const std::filesystem::path& base);
/// build_project of a project file validated by identify_schema().
Project build_project(const io::Node& root, const std::filesystem::path& base);

/// How to run one identification.
struct IdentifyRequest {
  std::filesystem::path base;  ///< the folder `experiment.dir` is relative to (the project file's)
  /// DIR: result.json, history.csv, checkpoint.json, plots/, written in DIR/.tricot-identify/ and
  /// published at the end (OutputDir).
  std::filesystem::path out;
  /// Continue a killed run from its checkpoint (DIR/.tricot-identify/checkpoint.json); a finished
  /// run (DIR/checkpoint.json in phase done) is left as it is (IdentifyOutcome::already_finished).
  bool resume = false;
  bool plots = true;          ///< plots/*.png through gnuplot
  bool print_summary = true;  ///< the table of coefficients at the end
  /// Testing aid: after this many checkpoints the process kills itself (SIGKILL), as a run killed
  /// mid-way; 0 = never.
  int kill_after = 0;
  /// Testing aid: the process kills itself as it starts this evaluation of the objective (LM or the
  /// stability test); 0 = never.
  int kill_after_evaluations = 0;
  /// Testing aid: the process kills itself once every output is staged, before publishing them.
  bool kill_before_publish = false;
  /// Called after each checkpoint is written (the demo's ε study reads the run from them).
  std::function<void(const ident::Checkpoint&)> observe;
  /// Called with the objective once it is built, before any evaluation; may be empty. `tricot
  /// identify` under mpirun spreads its tests over the ranks here (mpi::World::lead).
  std::function<void(ident::Objective&)> distribute;
  /// The processes `distribute` spreads the tests over (the MPI world's size), for result.json's
  /// "ranks" and the first log line; 1 without MPI.
  int ranks = 1;
};

struct IdentifyOutcome {
  ident::IdentifyResult result;
  std::optional<Truth> truth;  ///< the experiment's truth.json, when it has one
  int residuals = 0;           ///< N, the data values in f
  std::string data;            ///< the data groups, e.g. "tension/edge_displacement (35)"
  int dofs = 0;                ///< of the identification mesh (first test)
  /// [identify] coarse_mesh: each level's run (result holds the last one's, with the project's start
  /// and the whole wall time) and its dofs (first test); empty otherwise.
  std::optional<ident::LevelsResult> levels;
  std::vector<int> level_dofs;
  /// `--resume` found the run finished: nothing was run or written; `result` is the checkpoint's.
  bool already_finished = false;
  int ranks = 1;    ///< MPI processes that simulated the tests (IdentifyRequest::ranks)
  int threads = 1;  ///< OpenMP threads per process for the tests ([identify] threads, resolved)
};

/// Runs the identification of a validated project: reads the experiment, builds the objective,
/// runs LM with a checkpoint after every accepted step, and writes result.json, history.csv and
/// plots/history.png (plots/fit_<test>.png for the edge data) to `request.out`.
/// Throws InputError for a bad project or data (FileError when a file is missing).
/// The end-of-run table: termination, then per coefficient its start, identified value and standard
/// error (and the truth's error when the experiment has one), the least identifiable direction.
void print_summary(const IdentifyOutcome& o, const std::filesystem::path& out, const Log& log);

IdentifyOutcome run_identification(const IdentificationSpec& spec, const IdentifyRequest& request, const Log& log);
/// run_identification of a project file validated by identify_schema().
IdentifyOutcome run_identification(const io::Node& root, const IdentifyRequest& request, const Log& log);

}  // namespace tricot::project
