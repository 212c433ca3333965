// tricot relax: a relaxation log → Prony fits, a plot, the quasi-static verdict (see relax.hpp).
#include "tricot/project/relax.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "output/plot.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"

namespace tricot::project {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

RelaxRun run_relax(const RelaxSpec& spec, const fs::path& dir, const Log& log) {
  spec.options.validate();
  const io::LogTable table = io::read_log(spec.log);
  const std::vector<double> t = table.times(spec.time_column), f = table.numbers(spec.force_column);
  const std::vector<double> c =
      spec.crosshead_column.empty() ? std::vector<double>{} : table.numbers(spec.crosshead_column);
  RelaxRun run;
  run.result = lab::fit_relaxation(t, f, c, spec.options, spec.log);
  const lab::RelaxationResult& r = run.result;
  if (spec.duration_s) run.verdict = lab::quasi_static(r.best(), *spec.duration_s, spec.options.quasi_static_tolerance);

  fs::create_directories(dir);
  json j;
  j["log"] = spec.log;
  j["termination"] = r.termination == lab::RelaxationTermination::converged ? "converged" : "not_converged";
  j["tare_N"] = r.tare_N;
  j["tare_estimated"] = r.tare_estimated;
  j["hold_start_s"] = r.hold_start_s;
  j["hold_end_s"] = r.hold_end_s;
  j["chosen_terms"] = r.chosen_terms;
  j["fits"] = json::array();
  for (const lab::PronyFit& p : r.fits) {
    json terms = json::array();
    for (const auto& term : p.terms) terms.push_back({{"amplitude_N", term.amplitude_N}, {"tau_s", term.tau_s}});
    j["fits"].push_back({{"terms", terms},
                         {"relaxed_N", p.relaxed_N},
                         {"relaxed_ratio", p.relaxed_ratio()},
                         {"rms_N", p.rms_N},
                         {"bic", p.bic},
                         {"aic", p.aic},
                         {"converged", p.converged}});
  }
  if (run.verdict)
    j["quasi_static"] = {{"duration_s", run.verdict->duration_s},
                         {"viscous_excess", run.verdict->viscous_excess},
                         {"tolerance", spec.options.quasi_static_tolerance},
                         {"quasi_static", run.verdict->quasi_static},
                         {"min_duration_s", run.verdict->min_duration_s}};
  io::write_atomic(dir / "relax.json", j.dump(2) + "\n");

  std::vector<std::string> columns{"time", "hold_time", "force"};
  for (std::size_t m = 1; m <= r.fits.size(); ++m) columns.push_back(fmt::format("fit_{}", m));
  io::CsvWriter csv;
  csv.row(columns);
  constexpr io::CsvFormat kDigits = io::CsvFormat::significant(9);  // the plot's data
  for (std::size_t i = r.hold_first; i <= r.hold_last; ++i) {
    const double s = t[i] - r.hold_start_s;
    csv.number(t[i], kDigits).number(s, kDigits).number(f[i] - r.tare_N, kDigits);
    for (const auto& p : r.fits) csv.number(p.force(s), kDigits);
    csv.end_row();
  }
  io::write_atomic(dir / "relax.csv", csv.take());

  std::string curves;
  for (std::size_t m = 1; m <= r.fits.size(); ++m)
    curves += fmt::format(", '' using 2:{} with lines lw 2 title \"{} term{}{}\"", m + 3, m, m > 1 ? "s" : "",
                          int(m) == r.chosen_terms ? " (chosen by BIC)" : "");
  plot({.png = dir / "relax.png", .width = 900, .height = 600, .name = "relax.png"},
       fmt::format("set title \"{}\" noenhanced font \",9\"\nset xlabel \"time since the hold began (s)\"\n"
                   "set ylabel \"force, tare removed (N)\"\nset key top right\n"
                   "plot {} using 2:3 with points pt 7 ps 0.3 lc rgb \"#999999\" title \"log\"{}\n",
                   r.brief_report(), io::gnuplot_quote(dir / "relax.csv"), curves),
       log);
  log.print(r.brief_report());
  if (run.verdict)
    log.print(fmt::format(
        "a test of {:.0f} s is {}quasi-static: viscous excess {:.2f} % of the relaxed force (tolerance {:.1f} %); "
        "quasi-static from {:.0f} s",
        run.verdict->duration_s, run.verdict->quasi_static ? "" : "NOT ", 100 * run.verdict->viscous_excess,
        100 * spec.options.quasi_static_tolerance, run.verdict->min_duration_s));
  log.print("wrote " + (dir / "relax.json").string() + ", relax.csv, relax.png");
  return run;
}

}  // namespace tricot::project
