// tricot identify's pipeline: the project's objective, LM with a checkpoint after every accepted step
// (resume included), and the outputs (docs/theory.md §1–§3, §7, §8; paper §2).
#include "tricot/project/identification.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <atomic>
#include <csignal>
#include <system_error>

#include "output/identification_outputs.hpp"
#include "output/identification_report.hpp"
#include "tricot/ident/problem.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/checkpoint.hpp"
#include "tricot/project/output_dir.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

// Testing aid (IdentifyRequest::kill_after_evaluations): the objective, killing the process (SIGKILL)
// as it starts its n-th evaluation, in LM or in the stability test; n = 0 never.
class KillAfterEvaluations final : public ident::Problem {
 public:
  KillAfterEvaluations(const ident::Problem& p, int n) : p_(p), n_(n) {}
  const std::vector<ident::Parameter>& parameters() const override { return p_.parameters(); }
  int residuals() const override { return p_.residuals(); }
  ident::Evaluation evaluate(const Eigen::VectorXd& J, bool jacobian) const override {
    if (n_ > 0 && ++count_ >= n_) std::raise(SIGKILL);
    return p_.evaluate(J, jacobian);
  }
  bool has_exact_jacobian() const override { return p_.has_exact_jacobian(); }
  Eigen::VectorXd residual_variance() const override { return p_.residual_variance(); }
  double lower_bound(const Eigen::VectorXd& J) const override { return p_.lower_bound(J); }
  bool has_lower_bound() const override { return p_.has_lower_bound(); }
  bool keeps_simulations() const override { return p_.keeps_simulations(); }

 private:
  const ident::Problem& p_;
  int n_;
  mutable std::atomic<int> count_{0};
};

// `--resume` on a finished run: nothing to do, result.json and the rest stay as they are.
IdentifyOutcome finished_run(const ident::Checkpoint& c, const fs::path& out, const Log& log, IdentifyOutcome outcome) {
  ident::IdentifyResult& r = outcome.result;
  r.termination = c.termination;
  r.message = c.message;
  r.names = c.names;
  r.parameters = c.parameters;
  r.objective = c.objective;
  r.iterations = c.iterations;
  r.evaluations = c.evaluations;
  r.restarts = c.restarts;
  r.stability_passed = c.stability_passed;
  r.history = c.history;
  outcome.already_finished = true;
  log.print(
      fmt::format("identify: nothing to resume: the run in {} finished ({}, {} LM iterations); {} is left as it is",
                  out.string(), ident::to_string(c.termination), c.iterations, (out / "result.json").string()));
  return outcome;
}

}  // namespace

IdentifyOutcome run_identification(const io::Node& root, const IdentifyRequest& req, const Log& log) {
  return run_identification(read_identification_spec(root), req, log);
}

IdentifyOutcome run_identification(const IdentificationSpec& spec, const IdentifyRequest& req, const Log& log) {
  const auto started = std::chrono::steady_clock::now();
  Project P = build_project(spec, req.base);
  if (P.coarse_objective && req.resume)  // identify_by_levels starts afresh
    spec.identify.origin.fail("coarse_mesh", "a run by mesh levels cannot be resumed",
                              "--resume with coarse_mesh = " + io::to_toml(spec.identify.coarse_mesh),
                              "a fresh run, or coarse_mesh = [] to resume a run on the project's meshes");
  if (req.distribute) req.distribute(*P.objective);
  const auto& law = P.law;
  const auto& models = P.models;
  auto& options = P.options;
  const auto& objective = P.objective;
  const auto& parameters = objective->parameters();
  IdentifyOutcome outcome;
  outcome.ranks = req.ranks;
  outcome.threads = ident::thread_team(options.threads);
  outcome.truth = P.truth;
  outcome.residuals = objective->residuals();
  outcome.dofs = models.front().mesh.dofs();
  for (const auto& g : objective->data().groups())
    outcome.data += fmt::format("{}{} ({})", outcome.data.empty() ? "" : ", ", g.name, g.size);

  // Checkpoints belong to these data and this model; [identify] may change between runs. The run
  // writes in its staging folder (checkpoint.json included) and publishes at the end (issue 14).
  const std::string fingerprint = project::fingerprint(*objective, *law, models);
  const fs::path kept = OutputDir::staging_of(req.out, "identify") / kCheckpointFile;
  const fs::path published = req.out / kCheckpointFile;
  std::error_code ec;
  if (req.resume && !fs::exists(kept, ec) && !fs::exists(published, ec))
    read_checkpoint(published, fingerprint);  // FileError naming DIR/checkpoint.json: nothing to resume
  OutputDir output(req.out, "identify", /*keep_staging=*/req.resume);  // completes a killed publication
  if (req.resume) {
    if (fs::exists(kept, ec)) {
      options.resume_from = read_checkpoint(kept, fingerprint);
    } else {  // no run under way: the last published one; finished, it is left as it is
      options.resume_from = read_checkpoint(published, fingerprint);
      if (options.resume_from->phase == ident::Phase::done)
        return finished_run(*options.resume_from, req.out, log, std::move(outcome));
    }
  }
  const fs::path dir = output.staging();
  const fs::path checkpoint = dir / kCheckpointFile;
  int checkpoints = 0;
  options.on_checkpoint = [&](const ident::Checkpoint& c) {
    write_checkpoint(checkpoint, c, fingerprint);
    if (req.observe) req.observe(c);
    if (req.kill_after > 0 && ++checkpoints >= req.kill_after) std::raise(SIGKILL);  // testing aid
  };
  // LM minimises the objective, or the objective with the stability barrier ([stability]).
  const ident::Problem& minimised = P.stability ? static_cast<const ident::Problem&>(*P.stability) : *objective;
  const KillAfterEvaluations killer(minimised, req.kill_after_evaluations);  // testing aid

  log.print(fmt::format(
      "identify: {} coefficients of {} from {} values ({}), {} dofs, {} Jacobian, {} MPI rank{} × {} thread{}{}",
      parameters.size(), law->name(), outcome.residuals, outcome.data, outcome.dofs, ident::to_string(options.jacobian),
      outcome.ranks, outcome.ranks == 1 ? "" : "s", outcome.threads, outcome.threads == 1 ? "" : "s",
      req.resume ? fmt::format(", resumed at iteration {}", options.resume_from->iterations) : ""));
  if (P.stability)
    log.print(fmt::format("identify: with the stability barrier ({} rows)", P.stability->barrier_rows()));
  const double outside = spec.data.domain_weight;  // 0: left out (restricted), else the weight (weighted)
  for (const ident::RestrictedTest& t : P.restriction) {
    const std::string rest = outside > 0 ? fmt::format("weigh {:g}", outside) : std::string("left out");
    log.print(
        t.kept == 0
            ? fmt::format("identify: domain: {} {} (held {:.3f}, pulled {:.3f} at step 1)", t.name,
                          outside > 0 ? "steps 1–" + std::to_string(t.steps) + " " + rest : rest, t.held, t.pulled)
        : t.kept == t.steps
            ? fmt::format("identify: domain: {} keeps steps 1–{} of {} (held {:.3f}, pulled to {:.3f})", t.name, t.kept,
                          t.steps, t.held, t.pulled)
            : fmt::format("identify: domain: {} keeps steps 1–{} of {}, steps {}–{} {} (held {:.3f}, pulled to {:.3f})",
                          t.name, t.kept, t.steps, t.kept + 1, t.steps, rest, t.held, t.pulled));
  }
  if (P.coarse_objective) {  // [identify] coarse_mesh: LM on the coarse level, then the corrected one
    const ident::Problem& coarse =
        P.coarse_stability ? static_cast<const ident::Problem&>(*P.coarse_stability) : *P.coarse_objective;
    log.print(
        fmt::format("identify: by mesh levels: {} dofs first ([identify] coarse_mesh), then {} through the coarse "
                    "model corrected to it",
                    P.coarse_models.front().mesh.dofs(), outcome.dofs));
    ident::IdentifyOptions by_levels = options;
    by_levels.on_checkpoint = {};  // LM's state on the coarse level is no state to resume the fine one from
    outcome.levels = ident::identify_by_levels({&coarse, &killer}, by_levels, log.reporter());
    const ident::LevelsResult& levels = *outcome.levels;
    outcome.level_dofs = {P.coarse_models.front().mesh.dofs(), outcome.dofs};
    for (std::size_t l = 0; l < levels.levels.size(); ++l)
      log.print(fmt::format("identify: level {} ({} dofs): {}", l + 1, outcome.level_dofs[l],
                            levels.levels[l].brief_report()));
    if (levels.levels.size() > 1)
      log.print(fmt::format("identify: {} evaluations of the coarse level inside the corrected models",
                            levels.coarse_evaluations));
    outcome.result = levels.result;
    outcome.result.start = levels.levels.front().start;
    outcome.result.wall_seconds = levels.wall_seconds;
  } else {
    outcome.result = ident::identify(killer, options, log.reporter());
  }

  // Outputs.
  json result = result_json(outcome, *objective, req.resume);
  const bool eq9 = !P.eq9_points[0].empty() || !P.eq9_points[1].empty();
  const std::unique_ptr<fem::Law> identified = objective->law_at(outcome.result.parameters);
  if (eq9) result["eq9"] = eq9_json(P.eq9_points, *identified, P.eq9_practical, P.eq9_min_held_levels);
  if (!P.restriction.empty()) {  // [data] domain_course, domain_wale: what each test kept
    json tests = json::object();
    for (const ident::RestrictedTest& t : P.restriction)
      tests[t.name] = {{"steps", t.steps}, {"kept", t.kept}, {"held", t.held}, {"pulled", t.pulled}};
    result["domain"] = {
        {"tests", tests}, {"mode", outside > 0 ? "weighted" : "restricted"}, {"outside_weight", outside}};
  }
  // ∂r/∂J at the answer, for the identifiability report and the design suggestion.
  const ident::Evaluation at_answer = outcome.result.termination == ident::Termination::fe_failure
                                          ? ident::Evaluation{}
                                          : objective->evaluate(outcome.result.parameters, true);
  result["identifiability"] = identifiability_json(*objective, outcome.result, at_answer, P.identifiability);
  if (spec.design) result["design"] = design_json(spec, P, outcome.result, at_answer, log);
  if (req.plots) fs::create_directories(dir / "plots");
  // Each test's fit (issue 29): its force RMS (and as a fraction of its peak) and its tracked points'
  // RMS residual, with fit_field_<test>.csv and the residual maps.
  if (outcome.result.termination != ident::Termination::fe_failure) {
    nlohmann::ordered_json fits = nlohmann::ordered_json::object();
    for (const TestFit& f : write_fit_field(dir, *objective, outcome.result, req.plots, log)) {
      auto& j = fits[f.name];
      j["force_rms_N"] =
          std::isfinite(f.force_rms_N) ? nlohmann::ordered_json(f.force_rms_N) : nlohmann::ordered_json();
      j["force_rms_of_peak"] = std::isfinite(f.force_rms_N) && f.force_peak_N > 0
                                   ? nlohmann::ordered_json(f.force_rms_N / f.force_peak_N)
                                   : nlohmann::ordered_json();
      j["points_rms_mm"] =
          std::isfinite(f.points_rms_mm) ? nlohmann::ordered_json(f.points_rms_mm) : nlohmann::ordered_json();
      if (std::isfinite(f.wrinkled_area)) j["wrinkled_area"] = f.wrinkled_area, j["slack_area"] = f.slack_area;
    }
    result["fit"] = fits;
  }
  io::write_atomic(dir / "result.json", result.dump(2) + "\n");
  write_history(dir / "history.csv", outcome.result);
  if (outcome.result.termination != ident::Termination::fe_failure)
    write_fit(dir, *objective, outcome.result, req.plots, log);
  if (req.plots) plot_history(dir, outcome, log);
  if (eq9) write_eq9(dir, P.eq9_points, *identified, P.eq9_practical, req.plots, log);
  if (req.print_summary) print_summary(outcome, req.out, log);
  write_identification_report(spec, P, outcome, dir,
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  if (req.kill_before_publish) std::raise(SIGKILL);  // testing aid
  output.publish();
  return outcome;
}

}  // namespace tricot::project
