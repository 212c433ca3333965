// The checkpoint of an identification (DIR/checkpoint.json): ident's Checkpoint plus a fingerprint of
// the data and the model it belongs to, so that `--resume` refuses a checkpoint of another project.
#include "tricot/project/checkpoint.hpp"

#include <fmt/format.h>

#include <optional>

#include "output/json.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;

// FNV-1a over bytes: the checkpoint's fingerprint of the data and the model it belongs to.
struct Fingerprint {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  void add(const Eigen::VectorXd& v) { add(v.data(), sizeof(double) * static_cast<std::size_t>(v.size())); }
  void add(const std::string& s) { add(s.data(), s.size()); }
  std::string hex() const { return fmt::format("{:016x}", h); }
};

std::optional<ident::Termination> termination_from_string(const std::string& s) {
  using T = ident::Termination;
  for (T t : {T::objective_below_epsilon, T::step_below_delta, T::objective_stalled, T::gradient_below_tolerance,
              T::max_iterations, T::unstable, T::fe_failure})
    if (s == ident::to_string(t)) return t;
  return std::nullopt;
}

}  // namespace

std::string fingerprint(const ident::Objective& objective, const fem::Law& law,
                        const std::vector<fem::TestModel>& models) {
  Fingerprint fp;
  fp.add(objective.data().measured());
  fp.add(objective.data().factors());
  for (const auto& p : objective.parameters()) {
    fp.add(p.name);
    fp.add(&p.start, sizeof p.start);
    const double s = p.resolved_scale();
    fp.add(&s, sizeof s);
  }
  fp.add(law.coefficients());
  for (const auto& m : models) fp.add(m.mesh.X.reshaped().eval());
  return fp.hex();
}

void write_checkpoint(const fs::path& file, const ident::Checkpoint& c, const std::string& fingerprint) {
  json j;
  j["fingerprint"] = fingerprint;
  j["names"] = c.names;
  j["scales"] = vec_json(c.scales);
  j["x"] = vec_json(c.x);
  j["parameters"] = vec_json(c.parameters);
  j["objective"] = c.objective;
  j["trust_region_radius"] = c.trust_region_radius;
  j["iterations"] = c.iterations;
  j["evaluations"] = c.evaluations;
  j["jacobian_evaluations"] = c.jacobian_evaluations;
  j["failed_evaluations"] = c.failed_evaluations;
  j["skipped_evaluations"] = c.skipped_evaluations;
  j["restarts"] = c.restarts;
  j["wall_seconds"] = c.wall_seconds;
  j["phase"] = ident::to_string(c.phase);
  j["termination"] = ident::to_string(c.termination);
  j["message"] = c.message;
  j["stability_passed"] = c.stability_passed;
  j["held"] = c.held;
  json h = json::array();
  for (const auto& e : c.history)
    h.push_back({{"iteration", e.iteration},
                 {"objective", e.objective},
                 {"parameters", vec_json(e.parameters)},
                 {"restart", e.restart}});
  j["history"] = h;
  io::write_atomic(file, j.dump(1) + "\n");
}

ident::Checkpoint read_checkpoint(const fs::path& file, const std::string& fingerprint) {
  if (!fs::exists(file))
    throw FileError({file.string(), 0, ""}, "nothing to resume: no checkpoint in the output folder", "",
                    "the -o folder of an earlier run of this project");
  json j;
  try {
    j = json::parse(io::read_text(file));
  } catch (const json::exception& e) {
    throw InputError({file.string(), 0, ""}, "not a tricot checkpoint: " + json_problem(e));
  }
  const std::string f = file.string();
  if (json_get<std::string>(j, "fingerprint", f) != fingerprint)
    throw InputError({f, 0, "fingerprint"},
                     "the checkpoint belongs to other data or another model (the experiment, [law], [mesh], "
                     "[[test]], [[parameter]] or [data] changed); run without --resume to start afresh");
  ident::Checkpoint c;
  c.names = json_get<std::vector<std::string>>(j, "names", f);
  c.scales = json_get_vec(j, "scales", f);
  c.x = json_get_vec(j, "x", f);
  c.parameters = json_get_vec(j, "parameters", f);
  c.objective = json_get<double>(j, "objective", f);
  c.trust_region_radius = json_get<double>(j, "trust_region_radius", f);
  c.iterations = json_get<int>(j, "iterations", f);
  c.evaluations = json_get<int>(j, "evaluations", f);
  c.jacobian_evaluations = json_get<int>(j, "jacobian_evaluations", f);
  c.failed_evaluations = json_get<int>(j, "failed_evaluations", f);
  c.skipped_evaluations = json_get_or(j, "skipped_evaluations", 0, f);  // none before stop 24
  c.restarts = json_get<int>(j, "restarts", f);
  c.wall_seconds = json_get<double>(j, "wall_seconds", f);
  // A checkpoint written before issue 14 has no phase: LM under way.
  const auto phase_name = json_get_or(j, "phase", std::string("lm"), f);
  const auto phase = ident::phase_from_string(phase_name);
  if (!phase) throw InputError({f, 0, "phase"}, "unknown phase", phase_name, "lm, stability or done");
  c.phase = *phase;
  const auto termination_name = json_get_or(j, "termination", std::string("fe_failure"), f);
  const auto termination = termination_from_string(termination_name);
  if (!termination)
    throw InputError({f, 0, "termination"}, "unknown termination", termination_name, "a termination of result.json");
  c.termination = *termination;
  c.message = json_get_or(j, "message", std::string(), f);
  c.stability_passed = json_get_or(j, "stability_passed", false, f);
  if (j.contains("held")) c.held = json_get<std::vector<int>>(j, "held", f);  // none before stop 22
  for (int k : c.held)
    if (k < 0 || k >= c.x.size())
      throw InputError({f, 0, "held"}, "not an index of x", std::to_string(k), "0 to n - 1");
  const json history = json_get<json>(j, "history", f);
  if (!history.is_array()) throw InputError({f, 0, "history"}, "of the wrong type", history.dump(), "an array");
  for (std::size_t i = 0; i < history.size(); ++i) {
    const json& e = history[i];
    const std::string at = fmt::format("history[{}].", i);
    c.history.push_back({json_get<int>(e, "iteration", f, at), json_get<double>(e, "objective", f, at),
                         json_get_vec(e, "parameters", f, at), json_get<int>(e, "restart", f, at)});
  }
  return c;
}

}  // namespace tricot::project
