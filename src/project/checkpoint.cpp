// The checkpoint of an identification (DIR/checkpoint.json): ident's Checkpoint plus a fingerprint of
// the data and the model it belongs to, so that `--resume` refuses a checkpoint of another project.
#include "tricot/project/checkpoint.hpp"

#include <fmt/format.h>

#include <optional>

#include "json.hpp"
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

std::string fingerprint(const ident::Objective& objective, const fem::Law& law, const std::vector<fem::TestModel>& models) {
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
  j["restarts"] = c.restarts;
  j["wall_seconds"] = c.wall_seconds;
  j["phase"] = ident::to_string(c.phase);
  j["termination"] = ident::to_string(c.termination);
  j["message"] = c.message;
  j["stability_passed"] = c.stability_passed;
  json h = json::array();
  for (const auto& e : c.history)
    h.push_back({{"iteration", e.iteration}, {"objective", e.objective}, {"parameters", vec_json(e.parameters)},
                 {"restart", e.restart}});
  j["history"] = h;
  io::write_atomic(file, j.dump(1) + "\n");
}

ident::Checkpoint read_checkpoint(const fs::path& file, const std::string& fingerprint) {
  if (!fs::exists(file))
    throw FileError({file.string(), 0, ""}, "nothing to resume: no checkpoint in the output folder", "",
                    "the -o folder of an earlier run of this project");
  ident::Checkpoint c;
  try {
    const json j = json::parse(io::read_text(file));
    if (j.at("fingerprint").get<std::string>() != fingerprint)
      throw InputError({file.string(), 0, "fingerprint"},
                       "the checkpoint belongs to other data or another model (the experiment, [law], [mesh], "
                       "[[test]], [[parameter]] or [data] changed); run without --resume to start afresh");
    c.names = j.at("names").get<std::vector<std::string>>();
    c.scales = json_vec(j.at("scales"));
    c.x = json_vec(j.at("x"));
    c.parameters = json_vec(j.at("parameters"));
    c.objective = j.at("objective").get<double>();
    c.trust_region_radius = j.at("trust_region_radius").get<double>();
    c.iterations = j.at("iterations").get<int>();
    c.evaluations = j.at("evaluations").get<int>();
    c.jacobian_evaluations = j.at("jacobian_evaluations").get<int>();
    c.failed_evaluations = j.at("failed_evaluations").get<int>();
    c.restarts = j.at("restarts").get<int>();
    c.wall_seconds = j.at("wall_seconds").get<double>();
    // A checkpoint written before issue 14 has no phase: LM under way.
    const std::string phase_name = j.value("phase", std::string("lm"));
    const auto phase = ident::phase_from_string(phase_name);
    if (!phase) throw InputError({file.string(), 0, "phase"}, "unknown phase", phase_name, "lm, stability or done");
    c.phase = *phase;
    const std::string termination_name = j.value("termination", std::string("fe_failure"));
    const auto termination = termination_from_string(termination_name);
    if (!termination)
      throw InputError({file.string(), 0, "termination"}, "unknown termination", termination_name,
                       "a termination of result.json");
    c.termination = *termination;
    c.message = j.value("message", std::string());
    c.stability_passed = j.value("stability_passed", false);
    for (const json& e : j.at("history"))
      c.history.push_back({e.at("iteration").get<int>(), e.at("objective").get<double>(), json_vec(e.at("parameters")),
                           e.at("restart").get<int>()});
  } catch (const json::exception& e) {
    throw InputError({file.string(), 0, ""}, std::string("not a tricot checkpoint: ") + e.what());
  }
  return c;
}

}  // namespace tricot::project
