// The verbs from Python (results.hpp): flags → spec → the project layer's pipeline → result objects,
// as apps/tricot/*.cpp do for the command line.
#include "results.hpp"

#include <fmt/format.h>

#include <algorithm>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "run.hpp"
#include "spec.hpp"
#include "tricot/dic/icgn.hpp"
#include "tricot/io/files.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/dic_run.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/lab_experiment.hpp"
#include "tricot/project/simulation.hpp"
#include "tricot/project/synthesis.hpp"

namespace tricot::python {

namespace fs = std::filesystem;

py::dict table_dict(const fs::path& csv) {
  const io::Table t = io::read_csv(csv);
  py::dict d;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    std::vector<double> column(t.rows.size());
    for (std::size_t r = 0; r < t.rows.size(); ++r) column[r] = t.rows[r][c];
    d[py::str(t.columns[c])] = adopt(std::move(column), {py::ssize_t(t.rows.size())});
  }
  return d;
}

namespace {

py::array_t<double> vector_array(const Eigen::VectorXd& v) {
  return adopt(std::vector<double>(v.data(), v.data() + v.size()), {py::ssize_t(v.size())});
}

py::array_t<double> matrix_array(const Eigen::MatrixXd& m) {
  std::vector<double> rows(static_cast<std::size_t>(m.size()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index k = 0; k < m.cols(); ++k) rows[static_cast<std::size_t>(i * m.cols() + k)] = m(i, k);
  return adopt(std::move(rows), {py::ssize_t(m.rows()), py::ssize_t(m.cols())});
}

py::object truth_dict(const std::optional<project::Truth>& truth) {
  if (!truth) return py::none();
  py::dict d;
  for (std::size_t k = 0; k < truth->names.size(); ++k) d[py::str(truth->names[k])] = truth->values[k];
  return d;
}

/// The per-test tables of an output folder: DIR/<test>/<file> for every sub-folder holding it.
py::dict per_test(const fs::path& dir, const std::vector<std::string>& files) {
  std::vector<fs::path> folders;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_directory() && e.path().filename().string()[0] != '.') folders.push_back(e.path());
  std::sort(folders.begin(), folders.end());
  py::dict tests;
  for (const fs::path& f : folders) {
    py::dict tables;
    for (const std::string& file : files)
      if (fs::exists(f / file)) tables[py::str(fs::path(file).stem().string())] = table_dict(f / file);
    if (py::len(tables) > 0) tests[py::str(f.filename().string())] = tables;
  }
  return tests;
}

// ---- identify ----------------------------------------------------------------------------------

/// tricot.Identification: what `tricot identify` writes to result.json and history.csv, as arrays.
struct Identification {
  std::string out, termination, message, jacobian, brief_report;
  bool converged = false, already_finished = false;
  std::vector<std::string> names;
  py::object parameters, start, std_error, covariance, correlation, truth;
  double objective = 0, wall_seconds = 0;
  int iterations = 0, evaluations = 0, residuals = 0, dofs = 0;
  py::dict history, fits;
};

Identification identification_of(const project::IdentifyOutcome& o, const fs::path& out) {
  const ident::IdentifyResult& r = o.result;
  Identification p;
  p.out = out.string();
  p.termination = ident::to_string(r.termination);
  p.message = r.message;
  p.jacobian = r.jacobian == ident::JacobianMode::exact ? "exact" : "finite_difference";
  p.brief_report = r.brief_report();
  p.converged = r.converged();
  p.already_finished = o.already_finished;
  p.names = r.names;
  p.parameters = vector_array(r.parameters);
  p.start = vector_array(r.start);
  p.std_error = vector_array(r.uncertainty.std_error);
  p.covariance = matrix_array(r.uncertainty.covariance);
  p.correlation = matrix_array(r.uncertainty.correlation);
  p.truth = truth_dict(o.truth);
  p.objective = r.objective;
  p.wall_seconds = r.wall_seconds;
  p.iterations = r.iterations;
  p.evaluations = r.evaluations;
  p.residuals = o.residuals;
  p.dofs = o.dofs;
  // history.csv's columns: iteration, objective, restart, and the coefficients (entries × n).
  const std::size_t n = r.history.size(), np = r.names.size();
  std::vector<double> iteration(n), objective(n), restart(n), coefficients(n * np);
  for (std::size_t i = 0; i < n; ++i) {
    const ident::HistoryEntry& h = r.history[i];
    iteration[i] = h.iteration, objective[i] = h.objective, restart[i] = h.restart;
    for (std::size_t k = 0; k < np && k < std::size_t(h.parameters.size()); ++k)
      coefficients[i * np + k] = h.parameters(Eigen::Index(k));
  }
  p.history["iteration"] = adopt(std::move(iteration), {py::ssize_t(n)});
  p.history["objective"] = adopt(std::move(objective), {py::ssize_t(n)});
  p.history["restart"] = adopt(std::move(restart), {py::ssize_t(n)});
  p.history["parameters"] = adopt(std::move(coefficients), {py::ssize_t(n), py::ssize_t(np)});
  // DIR/fit_<test>.csv: the identified model against the measured edge data, per test.
  std::vector<fs::path> fits;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(out, ec)) {
    const std::string f = e.path().filename().string();
    if (f.rfind("fit_", 0) == 0 && e.path().extension() == ".csv") fits.push_back(e.path());
  }
  std::sort(fits.begin(), fits.end());
  for (const fs::path& f : fits) p.fits[py::str(f.stem().string().substr(4))] = table_dict(f);
  return p;
}

py::object identify(const py::object& spec, const py::object& out, bool resume, bool plots, const py::object& base,
                    const py::object& progress, const py::object& log, bool check) {
  const std::string dir = path_string(out);
  const LoadedSpec s = load_spec(spec, project::identify_schema(), base);
  check_out_dir(dir);
  const project::IdentificationSpec ispec = project::read_identification_spec(s.root);
  project::IdentifyRequest req;
  req.base = s.base;
  req.out = dir;
  req.resume = resume;
  req.plots = plots;
  Runner runner(progress, log);
  const project::Log lg = runner.log();
  const project::IdentifyOutcome o = runner.run([&] { return project::run_identification(ispec, req, lg); });
  py::object result = py::cast(identification_of(o, dir));
  if (check && !o.result.converged()) raise_not_converged(o.result.brief_report(), result);
  return result;
}

// ---- simulate ----------------------------------------------------------------------------------

struct Simulation {
  std::string out;
  std::vector<std::string> failures;
  py::dict tests;  ///< test → {"steps": steps.csv, "newton": newton.csv} (dicts of arrays)
};

py::object simulate(const py::object& spec, const py::object& out, const std::string& test, bool vtu, int vtu_every,
                    const py::object& base, const py::object& progress, const py::object& log, bool check) {
  const std::string dir = path_string(out);
  const LoadedSpec s = load_spec(spec, project::case_schema(), base);
  check_out_dir(dir);
  project::SimulationRequest req{dir, test, vtu, vtu_every, io::VtuFormat::binary, s.name, {}, {}};
  Runner runner(progress, log);
  const project::Log lg = runner.log();
  const project::SimulationOutcome o = runner.run([&] { return project::run_simulation(s.root, req, lg); });
  Simulation r{dir, o.failures, per_test(dir, {"steps.csv", "newton.csv"})};
  py::object result = py::cast(std::move(r));
  if (check && !o.failures.empty())  // the CLI's line (apps/tricot/simulate.cpp)
    raise_not_converged(
        fmt::format("{}: {}{}", s.name, o.failures.front(),
                    o.failures.size() > 1 ? fmt::format(" (and {} more tests)", o.failures.size() - 1) : ""),
        result);
  return result;
}

// ---- synth and experiment: an experiment folder ------------------------------------------------

struct Experiment {
  std::string out;
  py::dict tests;    ///< test → {"forces": forces.csv, "field": field.csv} (dicts of arrays)
  py::object truth;  ///< coefficient → true value (synth), or None
};

Experiment experiment_of(const fs::path& dir) {
  return {dir.string(), per_test(dir, {"forces.csv", "field.csv"}), truth_dict(project::read_truth(dir))};
}

Experiment synth(const py::object& spec, const py::object& out, const py::object& base, const py::object& progress,
                 const py::object& log) {
  const std::string dir = path_string(out);
  const LoadedSpec s = load_spec(spec, project::synth_schema(), base);
  check_out_dir(dir);
  Runner runner(progress, log);
  const project::Log lg = runner.log();
  runner.run([&] { return project::synthesize(s.root, dir, lg); });
  return experiment_of(dir);
}

Experiment experiment(const py::object& spec, const py::object& out, const py::object& base, const py::object& progress,
                      const py::object& log) {
  const std::string dir = path_string(out);
  const LoadedSpec s = load_spec(spec, project::lab_schema(), base);
  check_out_dir(dir);
  Runner runner(progress, log);
  const project::Log lg = runner.log();
  runner.run([&] { return project::run_lab_experiment(s.root, dir, lg); });
  return experiment_of(dir);
}

// ---- dic ---------------------------------------------------------------------------------------

struct DicRun {
  std::string out, termination, message;
  std::vector<std::string> warnings;
  py::dict fields;  ///< dic_arrays of the run
};

DicRun dic(const py::object& images, const py::object& out, const py::object& spec, const py::object& subset,
           const py::object& step, const std::string& mode, const py::object& roi, bool resume, const py::object& base,
           const py::object& progress, const py::object& log) {
  const std::string dir = path_string(out);
  std::vector<std::string> files;
  for (const py::handle& i : images) files.push_back(path_string(i));
  const LoadedSpec s = load_spec(spec, project::dic_schema(), base);
  check_out_dir(dir);
  if (files.empty()) throw InputError({"images", 0, ""}, "no image given", {}, "the reference image, then the frames");
  // The keywords over the spec, as the CLI's flags over the file (project::dic_spec).
  project::DicSpec d = project::DicSpec::from_config(s.root, s.base);
  apply_dic_keywords(d, subset, step, mode, roi);
  project::DicRunOptions options;
  options.resume = resume;
  options.keep_frames = true;  // the arrays of every frame
  Runner runner(progress, log);
  const project::Log lg = runner.log();
  const project::DicRun run = runner.run([&] { return project::run_dic(d, files, dir, lg, options); });
  return {dir, run.result.termination == dic::SequenceTermination::completed ? "completed" : "all_lost",
          run.result.message, run.warnings, dic_arrays(run.result)};
}

}  // namespace

void apply_dic_keywords(project::DicSpec& d, const py::object& subset, const py::object& step, const std::string& mode,
                        const py::object& roi) {
  dic::SequenceOptions& o = d.sequence;
  if (!subset.is_none())
    o.dic.icgn.subset_size = subset.cast<int>(), d.dic.origin.set_by_flag("subset_size", "subset=");
  if (!step.is_none()) o.dic.step = step.cast<int>(), d.dic.origin.set_by_flag("step", "step=");
  if (!mode.empty()) {
    d.dic.origin.set_by_flag("mode", "mode=");
    try {
      o.mode = value_of(option_of(&dic::SequenceOptions::mode), mode);
    } catch (const InputError& e) {
      d.rethrow(e);
    }
  }
  if (!roi.is_none()) {
    d.dic.roi = roi.cast<std::vector<double>>();
    d.dic.roi_polygon.clear();
    d.dic.roi_mask.clear();
    d.dic.origin.set_by_flag("roi", "roi=");
  }
}

py::dict dic_arrays(const dic::SequenceResult& r) {
  const std::size_t F = r.frames.size(), N = r.grid.size();
  std::vector<double> x0(N), y0(N);
  for (std::size_t k = 0; k < N; ++k) x0[k] = r.grid[k].x.x(), y0[k] = r.grid[k].x.y();
  std::vector<double> x(F * N), y(F * N), u(F * N), v(F * N), zncc(F * N), exx(F * N), eyy(F * N), exy(F * N);
  std::vector<double> sigma_u(F * N), sigma_v(F * N);
  std::vector<std::int8_t> status(F * N);
  std::vector<std::int32_t> frame(F), reference(F), ok(F);
  const double nan = std::nan("");
  for (std::size_t f = 0; f < F; ++f) {
    const dic::TrackedFrame& t = r.frames[f];
    frame[f] = t.frame, reference[f] = t.reference_frame, ok[f] = t.ok;
    for (std::size_t k = 0; k < N; ++k) {
      const std::size_t i = f * N + k;
      x[i] = k < t.x.size() ? t.x[k].x() : nan;
      y[i] = k < t.x.size() ? t.x[k].y() : nan;
      u[i] = x[i] - x0[k], v[i] = y[i] - y0[k];
      zncc[i] = k < t.zncc.size() ? t.zncc[k] : nan;
      status[i] = static_cast<std::int8_t>(k < t.status.size() ? t.status[k] : dic::PointStatus::not_computed);
      const bool strain = k < t.strain.size() && t.strain[k].valid;
      exx[i] = strain ? t.strain[k].exx : nan, eyy[i] = strain ? t.strain[k].eyy : nan,
      exy[i] = strain ? t.strain[k].exy : nan;
      sigma_u[i] = k < t.sigma.size() ? t.sigma[k].x() : nan;
      sigma_v[i] = k < t.sigma.size() ? t.sigma[k].y() : nan;
    }
  }
  const std::vector<py::ssize_t> fn{py::ssize_t(F), py::ssize_t(N)};
  py::dict d;
  d["frame"] = adopt(std::move(frame), {py::ssize_t(F)});
  d["reference_frame"] = adopt(std::move(reference), {py::ssize_t(F)});
  d["ok"] = adopt(std::move(ok), {py::ssize_t(F)});
  d["x0"] = adopt(std::move(x0), {py::ssize_t(N)});
  d["y0"] = adopt(std::move(y0), {py::ssize_t(N)});
  d["x"] = adopt(std::move(x), fn);
  d["y"] = adopt(std::move(y), fn);
  d["u"] = adopt(std::move(u), fn);
  d["v"] = adopt(std::move(v), fn);
  d["zncc"] = adopt(std::move(zncc), fn);
  d["status"] = adopt(std::move(status), fn);
  d["exx"] = adopt(std::move(exx), fn);
  d["eyy"] = adopt(std::move(eyy), fn);
  d["exy"] = adopt(std::move(exy), fn);
  d["sigma_u"] = adopt(std::move(sigma_u), fn);
  d["sigma_v"] = adopt(std::move(sigma_v), fn);
  return d;
}

void bind_verbs(py::module_& m) {
  using namespace py::literals;
  py::class_<Identification>(m, "Identification",
                             "The result of tricot.identify (result.json, history.csv, fit_<test>.csv).")
      .def_readonly("out", &Identification::out)
      .def_readonly("names", &Identification::names, "the identified coefficients")
      .def_readonly("parameters", &Identification::parameters, "J*, the coefficients found (array)")
      .def_readonly("start", &Identification::start)
      .def_readonly("std_error", &Identification::std_error)
      .def_readonly("covariance", &Identification::covariance)
      .def_readonly("correlation", &Identification::correlation)
      .def_readonly("objective", &Identification::objective, "f(J*), eq. 1")
      .def_readonly("iterations", &Identification::iterations)
      .def_readonly("evaluations", &Identification::evaluations)
      .def_readonly("residuals", &Identification::residuals, "N, the data values in f")
      .def_readonly("dofs", &Identification::dofs)
      .def_readonly("termination", &Identification::termination)
      .def_readonly("message", &Identification::message)
      .def_readonly("converged", &Identification::converged)
      .def_readonly("already_finished", &Identification::already_finished)
      .def_readonly("jacobian", &Identification::jacobian)
      .def_readonly("wall_seconds", &Identification::wall_seconds)
      .def_readonly("history", &Identification::history,
                    "iteration, objective, restart (arrays) and parameters (entries × coefficients)")
      .def_readonly("fits", &Identification::fits, "test → fit_<test>.csv's columns (model and measured edge data)")
      .def_readonly("truth", &Identification::truth, "coefficient → true value (synthetic experiments), or None")
      .def("brief_report", [](const Identification& i) { return i.brief_report; })
      .def("__repr__", [](const Identification& i) { return "<tricot.Identification " + i.brief_report + ">"; });
  py::class_<Simulation>(m, "Simulation", "The result of tricot.simulate.")
      .def_readonly("out", &Simulation::out)
      .def_readonly("failures", &Simulation::failures)
      .def_readonly("tests", &Simulation::tests, "test → {'steps': steps.csv, 'newton': newton.csv} as arrays");
  py::class_<Experiment>(m, "Experiment",
                         "An experiment folder (tricot.synth, tricot.experiment, tricot.read_experiment).")
      .def_readonly("out", &Experiment::out)
      .def_readonly("tests", &Experiment::tests, "test → {'forces': forces.csv, 'field': field.csv} as arrays")
      .def_readonly("truth", &Experiment::truth);
  py::class_<DicRun>(m, "DicRun", "The result of tricot.dic.")
      .def_readonly("out", &DicRun::out)
      .def_readonly("termination", &DicRun::termination)
      .def_readonly("message", &DicRun::message)
      .def_readonly("warnings", &DicRun::warnings)
      .def_readonly("fields", &DicRun::fields, "frames × points arrays: x, y, u, v, zncc, status, exx, eyy, exy, ...");

  m.def("identify", &identify, "spec"_a, "out"_a, py::kw_only(), "resume"_a = false, "plots"_a = true,
        "base"_a = py::none(), "progress"_a = py::none(), "log"_a = py::none(), "check"_a = true,
        R"(tricot identify SPEC -o OUT [--resume]: Levenberg–Marquardt identification.

spec: a project dict (the TOML file's tables) or the path of a project file; base: the folder a dict's
relative paths (experiment.dir) are taken from (default the current folder). Writes OUT as the CLI does.
progress(stage, done, total, detail) is called once per LM iteration (True: a line on stderr); Ctrl-C
stops the run with KeyboardInterrupt, leaving a checkpoint that resume=True continues from.
A run that does not converge raises NotConvergedError (its .result is the Identification) unless
check=False.)");
  m.def("simulate", &simulate, "spec"_a, "out"_a, py::kw_only(), "test"_a = "", "vtu"_a = true, "vtu_every"_a = 1,
        "base"_a = py::none(), "progress"_a = py::none(), "log"_a = py::none(), "check"_a = true,
        "tricot simulate SPEC -o OUT: the FE models of a case (dict or TOML path). Returns a Simulation.");
  m.def("synth", &synth, "spec"_a, "out"_a, py::kw_only(), "base"_a = py::none(), "progress"_a = py::none(),
        "log"_a = py::none(), "tricot synth SPEC -o OUT: a synthetic experiment. Returns an Experiment.");
  m.def("experiment", &experiment, "spec"_a, "out"_a, py::kw_only(), "base"_a = py::none(), "progress"_a = py::none(),
        "log"_a = py::none(),
        "tricot experiment SPEC -o OUT: a lab's raw files (a lab dict or TOML path) into an experiment. Returns an "
        "Experiment.");
  m.def(
      "read_experiment", [](const py::object& dir) { return experiment_of(path_string(dir)); }, "dir"_a,
      "An experiment folder's tables as arrays.");
  m.def("dic", &dic, "images"_a, "out"_a, py::kw_only(), "spec"_a = py::none(), "subset"_a = py::none(),
        "step"_a = py::none(), "mode"_a = "", "roi"_a = py::none(), "resume"_a = false, "base"_a = py::none(),
        "progress"_a = py::none(), "log"_a = py::none(),
        "tricot dic [SPEC] IMAGE... -o OUT: DIC over image files (the keywords override the spec as the CLI's flags). "
        "Returns a DicRun whose fields are arrays (frames × points).");
  m.def(
      "to_toml", [](const py::object& spec) { return to_toml(spec); }, "spec"_a,
      "The TOML text a spec dict is read as (the same reader as the CLI's files).");
  m.def(
      "print_config",
      [](const std::string& verb) {
        if (verb == "simulate") return io::print_config(project::case_schema());
        if (verb == "identify") return io::print_config(project::identify_schema());
        if (verb == "synth") return io::print_config(project::synth_schema());
        if (verb == "experiment") return io::print_config(project::lab_schema());
        if (verb == "dic") return io::print_config(project::dic_schema());
        throw InputError({"verb", 0, ""}, "no such verb", verb, "simulate, identify, synth, experiment or dic");
      },
      "verb"_a, "tricot VERB --print-config: the verb's fully commented default config.");
}

}  // namespace tricot::python
