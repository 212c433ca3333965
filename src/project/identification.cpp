// tricot identify's pipeline: the project's objective, LM with a checkpoint after every accepted step
// (resume included), and the outputs (THEORY §1–§3, §7, §8; paper §2).
#include "tricot/project/identification.hpp"

#include <fmt/format.h>

#include <chrono>
#include <csignal>

#include "identification_outputs.hpp"
#include "identification_report.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/checkpoint.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

IdentifyOutcome run_identification(const io::Node& root, const IdentifyRequest& req, const Log& log) {
  return run_identification(read_identification_spec(root), req, log);
}

IdentifyOutcome run_identification(const IdentificationSpec& spec, const IdentifyRequest& req, const Log& log) {
  const auto started = std::chrono::steady_clock::now();
  Project P = build_project(spec, req.base);
  const auto& law = P.law;
  const auto& models = P.models;
  const auto& solver = P.solver;
  auto& options = P.options;
  const auto& objective = P.objective;
  const auto& parameters = objective->parameters();
  IdentifyOutcome outcome;
  outcome.truth = P.truth;
  outcome.residuals = objective->residuals();
  outcome.dofs = models.front().mesh.dofs();
  for (const auto& g : objective->data().groups())
    outcome.data += fmt::format("{}{} ({})", outcome.data.empty() ? "" : ", ", g.name, g.size);

  // Checkpoints belong to these data and this model; [identify] may change between runs.
  const std::string fingerprint = project::fingerprint(*objective, *law, models);
  const fs::path checkpoint = req.out / kCheckpointFile;
  if (req.resume) options.resume_from = read_checkpoint(checkpoint, fingerprint);
  fs::create_directories(req.out);
  int checkpoints = 0;
  options.on_checkpoint = [&](const ident::Checkpoint& c) {
    write_checkpoint(checkpoint, c, fingerprint);
    if (req.observe) req.observe(c);
    if (req.kill_after > 0 && ++checkpoints >= req.kill_after) std::raise(SIGKILL);  // testing aid
  };

  log.print(fmt::format("identify: {} coefficients of {} from {} values ({}), {} dofs, {} Jacobian{}",
                            parameters.size(), law->name(), outcome.residuals, outcome.data, outcome.dofs,
                            ident::to_string(options.jacobian),
                            req.resume ? fmt::format(", resumed at iteration {}", options.resume_from->iterations) : ""));
  if (P.stability) log.print(fmt::format("identify: with the stability barrier ({} rows)", P.stability->barrier_rows()));
  outcome.result = P.stability ? ident::identify(*P.stability, options, log.reporter())
                               : ident::identify(*objective, options, log.reporter());

  // Outputs.
  json result = result_json(outcome, *objective, req.resume);
  const auto eq9_points_found = eq9_points(*objective, P.eq9_nearest);
  if (!eq9_points_found[0].empty() || !eq9_points_found[1].empty())
    result["eq9"] = eq9_json(*objective, outcome.result.parameters, P.eq9_practical, P.eq9_nearest);
  result["identifiability"] = identifiability_json(*objective, outcome.result, P.identifiability);
  io::write_atomic(req.out / "result.json", result.dump(2) + "\n");
  write_history(req.out / "history.csv", outcome.result);
  if (req.plots) fs::create_directories(req.out / "plots");
  if (outcome.result.termination != ident::Termination::fe_failure)
    write_fit(req.out, *objective, outcome.result, solver, req.plots, log);
  if (req.plots) plot_history(req.out, outcome, log);
  if (!eq9_points_found[0].empty() || !eq9_points_found[1].empty())
    write_eq9(req.out, *objective, outcome.result.parameters, P.eq9_practical, P.eq9_nearest, req.plots, log);
  if (req.print_summary) print_summary(outcome, req.out, log);
  write_identification_report(spec, P, outcome, req.out,
                              std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return outcome;
}

}  // namespace tricot::project
