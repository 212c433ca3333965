// tricot demo: the whole chain on the §4 campaign (see campaign_demo.hpp).
#include "tricot/project/campaign_demo.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "output/plot.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/config.hpp"
#include "tricot/io/files.hpp"
#include "tricot/io/log.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/dic_run.hpp"
#include "tricot/project/examples.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/identification_spec.hpp"
#include "tricot/project/lab_experiment.hpp"
#include "tricot/project/report.hpp"
#include "tricot/project/synth_images.hpp"
#include "tricot/project/synth_lab.hpp"
#include "tricot/project/synthesis.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// What the chain and its report need to know of the campaign, read from its experiment file and its
// DIC file: the tests, the images of each, the camera, the lab record's truth.
struct Campaign {
  std::vector<std::string> tests;         // [[test]] names
  int setting = 0, hold = 0, pull = 0;    // images after image 0: set, hold, pull
  int width = 0, height = 0;              // px
  double clock_offset_s = 0, tare_N = 0;  // the lab record's truth: log clock − camera clock, force at rest
  int subset_size = 0, step = 0;          // DIC, px
  std::size_t frames() const { return std::size_t(1 + setting + hold + pull); }
};

Campaign read_campaign(const io::Node& experiment, const DicSpec& dic) {
  Campaign c;
  const CaseSpec campaign = CaseSpec::from_config(experiment);
  for (const TestSpec& t : campaign.test) c.tests.push_back(t.name);
  c.setting = campaign.rig.setting_steps;
  const SynthImagesSpec images = SynthImagesSpec::from_config(experiment.section("synth").section("images"));
  c.hold = images.hold_frames;
  c.pull = campaign.test.front().steps;  // every test pulls in as many steps
  c.width = images.width, c.height = images.height;
  const SynthLabSpec lab = SynthLabSpec::from_config(experiment.section("synth").section("lab"));
  c.clock_offset_s = lab.clock_offset_s, c.tare_N = lab.tare_N;
  c.subset_size = dic.sequence.dic.icgn.subset_size, c.step = dic.sequence.dic.step;
  return c;
}

// User + system CPU seconds of the process, every thread.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// One stage: a progress line of its own (the engines' progress is counted into it), its timing.
class Stage {
 public:
  Stage(const Log& log, std::string name, std::size_t total)
      : log_(log), name_(std::move(name)), total_(total), wall0_(std::chrono::steady_clock::now()),
        cpu0_(cpu_seconds()) {
    log_.reporter().report({name_, 0, total_, ""});
  }
  // A Log for the stage's pipeline: `count` says which engine reports count toward the stage's total
  // (the engine's stage name), each by its `done`; the pipeline's lines go to the verbose log.
  Log inner(std::function<bool(const Progress&)> count) {
    Reporter r;
    r.progress = [this, count](const Progress& p) {
      if (!count(p)) return;
      std::size_t& d = done_by_[p.stage];
      d = std::max(d, p.done);
      std::size_t done = finished_;
      for (const auto& [k, v] : done_by_) done += v;
      if (total_ > 0) done = std::min(done, total_ - 1);  // the stage is done when finish() says so
      log_.reporter().report({name_, done, total_, p.stage + (p.detail.empty() ? "" : ": " + p.detail)});
    };
    const Reporter outer = log_.reporter();
    r.log = [outer](const std::string& l) { outer.info(l); };
    return Log(r, [outer](const std::string& l) { outer.info(l); });
  }
  // An engine stage ended: its count stays (a later one may reuse its name).
  void close_inner() {
    for (const auto& [k, v] : done_by_) finished_ += v;
    done_by_.clear();
  }
  StageTime finish(const std::string& detail) {
    StageTime t{name_, std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count(),
                cpu_seconds() - cpu0_};
    log_.reporter().report({name_, total_ > 0 ? total_ : 1, total_ > 0 ? total_ : 1, detail});
    return t;
  }

 private:
  const Log& log_;
  std::string name_;
  std::size_t total_;
  std::chrono::steady_clock::time_point wall0_;
  double cpu0_;
  std::map<std::string, std::size_t> done_by_;
  std::size_t finished_ = 0;
};

double number(const json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : NAN;
}

json read_json_file(const fs::path& f) { return json::parse(io::read_text(f)); }

// The DIC quality of every test over its last frame: each point at its place in the image, coloured
// by its ZNCC; lost points as black crosses. One panel per test (plots/dic_quality.png).
struct DicQuality {
  std::string name;
  int grid = 0, ok_last = 0, kept = 0;
  double mean_zncc = NAN, min_zncc = NAN;
};
std::vector<DicQuality> dic_quality(const fs::path& dic_dir, const fs::path& experiment, const Campaign& c,
                                    const fs::path& plots, const Log& log) {
  std::vector<DicQuality> q;
  const json sync = read_json_file(experiment / "sync.json");
  std::string panels;
  double floor = 0.99;  // the colour scale spans [floor, 1]: the worst point's ZNCC, at most 0.99
  for (const auto& name : c.tests) {
    const dic::SequenceResult seq = read_dic_folder(dic_dir / name);
    const auto& last = seq.frames.back();
    DicQuality d;
    d.name = name;
    d.grid = int(seq.grid.size());
    io::CsvWriter ok, lost;
    ok.row({"x", "y", "zncc"}), lost.row({"x", "y"});
    constexpr io::CsvFormat kShortest = io::CsvFormat::shortest();
    double sum = 0, lo = 1;
    for (std::size_t p = 0; p < seq.grid.size(); ++p) {
      if (last.status[p] == dic::PointStatus::ok) {
        ++d.ok_last, sum += last.zncc[p], lo = std::min(lo, last.zncc[p]);
        ok.number(last.x[p](0), kShortest).number(last.x[p](1), kShortest).number(last.zncc[p], kShortest).end_row();
      } else {
        lost.number(seq.grid[p].x(0), kShortest).number(seq.grid[p].x(1), kShortest).end_row();
      }
    }
    if (d.ok_last > 0) d.mean_zncc = sum / d.ok_last, d.min_zncc = lo;
    if (sync.contains(d.name)) d.kept = sync[d.name].value("points", 0);
    q.push_back(d);
    const fs::path a = plots / ("dic_" + d.name + "_ok.csv"), b = plots / ("dic_" + d.name + "_lost.csv");
    io::write_atomic(a, ok.take());
    io::write_atomic(b, lost.take());
    if (d.ok_last > 0) floor = std::min(floor, std::floor(100 * d.min_zncc) / 100);
    panels += fmt::format(
        "set title \"{} ({} of {} ok)\" noenhanced\nplot {} skip 1 using 1:2:3 with points pt 7 ps 0.6 palette", d.name,
        d.ok_last, d.grid, io::gnuplot_quote(a));
    if (d.ok_last < d.grid)
      panels += fmt::format(", {} skip 1 using 1:2 with points pt 2 ps 0.8 lc rgb \"black\"", io::gnuplot_quote(b));
    panels += "\n";
  }
  const std::string body = fmt::format(
      "set multiplot layout {},5 title \"DIC quality at the last frame: ZNCC of each point (lost points: black ×)\"\n"
      "set size ratio -1\nset xrange [0:{}]\nset yrange [{}:0]\nunset key\nset cbrange [{}:1]\n"
      "set palette defined (0 \"#b2182b\", 0.7 \"#fddbc7\", 1 \"#2166ac\")\nset format x \"\"\nset format y \"\"\n{}"
      "unset multiplot\n",
      c.tests.size() > 5 ? 2 : 1, c.width, c.height, floor, panels);
  plot({.png = plots / "dic_quality.png",
        .width = 1500,
        .height = c.tests.size() > 5 ? 700 : 380,
        .font_size = 10,
        .name = "dic_quality.png"},
       body, log);
  return q;
}

// The files of the campaign, one per verb, written to DIR: what each stage reads.
constexpr const char* kCampaignFiles[] = {"experiment.toml", "dic.toml", "lab.toml", "project-template.toml"};

// The paper's Table 5 (110 × 110 mm², 14 coefficients): eq. 9 whole and practical, course and wale.
constexpr double kPaperWhole[2] = {0.218, 0.313}, kPaperPractical[2] = {0.084, 0.079};

}  // namespace

std::string campaign_example(const CampaignDemoOptions& o) {
  return o.small ? "knit-campaign/demo/small" : "knit-campaign/demo";
}

CampaignDemoResult run_campaign_demo(const CampaignDemoOptions& o, const fs::path& out, const Log& log) {
  CampaignDemoResult result;
  fs::create_directories(out);
  for (const char* f : kCampaignFiles)
    io::write_atomic(out / f, std::string(example_file(campaign_example(o) + "/" + f)));
  const io::Node experiment = io::read_config(synth_schema(), (out / "experiment.toml").string());
  const DicSpec dic = dic_spec((out / "dic.toml").string(), {});
  const Campaign c = read_campaign(experiment, dic);
  const std::size_t n = c.tests.size(), frames = c.frames();
  log.print(fmt::format(
      "tricot demo: the §4 campaign of the reference knit, 110 × 110 mm², {} tests × {} images of {} × {} px "
      "(knit texture), load-cell logs at 100 Hz (clock offset {} s, tare {} N) → DIC → experiment → "
      "identify paper14 → report, in {}",
      n, frames, c.width, c.height, c.clock_offset_s, c.tare_N, out.string()));

  // 1. Render: FE of every test with the reference knit, its images and its lab record.
  {
    Stage st(log, "1/5 render", n * frames);
    synthesize(experiment, out / "raw", st.inner([](const Progress& p) { return p.stage.rfind("images ", 0) == 0; }));
    result.stages.push_back(
        st.finish(fmt::format("{} images and {} lab logs in {}", n * frames, n, (out / "raw").string())));
  }

  // 2. DIC of every test (tricot dic), incremental.
  {
    Stage st(log, "2/5 dic", n * (frames - 1));
    int ok = 0, points = 0;
    for (const auto& name : c.tests) {
      std::vector<std::string> images;
      for (const auto& f : list_images(out / "raw" / name / kImagesFolder)) images.push_back(f.string());
      DicRunOptions streamed;
      streamed.keep_frames = false;  // the tables are written frame by frame; only the last frame is held
      const DicRun run = run_dic(dic, images, out / "dic" / name,
                                 st.inner([](const Progress& p) { return p.stage == "dic"; }), streamed);
      st.close_inner();
      ok += run.result.frames.back().ok, points += int(run.result.grid.size());
    }
    result.stages.push_back(st.finish(fmt::format("{} of {} points ok at the last frames", ok, points)));
  }

  // 3. Sync and specimen coordinates (tricot experiment, reading the DIC folders).
  {
    Stage st(log, "3/5 sync", n);
    const io::Node root = io::read_config(lab_schema(), (out / "lab.toml").string());
    const LabExperimentResult lab = run_lab_experiment(
        root, out / "experiment", st.inner([](const Progress& p) { return p.stage == "experiment"; }));
    double worst = 0;
    for (const auto& t : lab.tests) worst = std::max(worst, std::abs(t.sync.clock_offset_s - c.clock_offset_s));
    result.stages.push_back(
        st.finish(fmt::format("{} tests; clock offsets within {:.1f} ms of the truth", lab.tests.size(), 1e3 * worst)));
  }

  // 4. Identification (tricot identify of the experiment's project.toml).
  IdentifyOutcome outcome;
  {
    Stage st(log, "4/5 identify", 0);
    const io::Node root = io::read_config(identify_schema(), (out / "experiment" / "project.toml").string());
    IdentifyRequest req;
    req.base = out / "experiment";
    req.out = out / "identify";
    req.print_summary = false;
    outcome = run_identification(root, req, st.inner([](const Progress& p) { return p.stage == "identify"; }));
    result.converged = outcome.result.converged();
    result.stages.push_back(st.finish(outcome.result.brief_report()));
  }

  // 5. The chain's sections of the report.
  {
    Stage st(log, "5/5 report", 1);
    const fs::path id = out / "identify";
    const fs::path plots = id / "plots";
    fs::create_directories(plots);
    const auto quality = dic_quality(out / "dic", out / "experiment", c, plots, log);
    std::error_code ec;
    fs::copy_file(out / "experiment" / "sync.png", plots / "sync.png", fs::copy_options::overwrite_existing, ec);
    const json sync = read_json_file(out / "experiment" / "sync.json");
    const json res = read_json_file(id / "result.json");
    // Forces recovered: each pull image's synchronised force against the lab record's truth.
    struct SyncRow {
      double offset, error_ms, tare, force_rms, force_max, peak;
    };
    std::vector<SyncRow> rows;
    for (const auto& name : c.tests) {
      const json truth = read_json_file(out / "raw" / name / "lab" / "truth.json");
      const json& s = sync[name];
      const io::LogTable f = io::read_log(out / "experiment" / name / "forces.csv", io::LogFormat{',', false, 1});
      const auto measured = f.numbers("edge_force");
      const auto& true_force = truth["force_N"];
      const std::size_t first = std::size_t(1 + c.setting + c.hold);
      double s2 = 0, worst = 0, peak = 0;
      for (std::size_t k = 0; k < measured.size(); ++k) {
        const double e = measured[k] - true_force[first + k].get<double>();
        s2 += e * e, worst = std::max(worst, std::abs(e));
        peak = std::max(peak, std::abs(true_force[first + k].get<double>()));
      }
      rows.push_back({number(s, "clock_offset_s"), 1e3 * (number(s, "clock_offset_s") - c.clock_offset_s),
                      number(s, "tare_N"), std::sqrt(s2 / double(std::max<std::size_t>(1, measured.size()))), worst,
                      peak});
    }
    report::append(id, [&](report::Document& d) {
      using namespace report;
      d.title = "tricot demo: the §4 campaign from images and load-cell logs to the knit's law";
      d.subtitle = fmt::format("{} tests of 110 × 110 mm² · {} images each of {} × {} px · paper14 · {}", n, frames,
                               c.width, c.height, result.converged ? "converged" : "NOT converged");
      {
        Section& s = d.section(kDic, "DIC quality per test");
        s.paragraph(
            fmt::format("tricot dic, incremental, second-order subsets ({}; dic.toml) on every test's {} images. The "
                        "points kept are those inside the specimen and measured in every image (the field of "
                        "experiment/<test>/field.csv).",
                        fmt::format("{} px subsets every {} px", c.subset_size, c.step), frames));
        s.figure(fs::path("plots") / "dic_quality.png",
                 "Every test's DIC points at its last frame, coloured by ZNCC; lost points as black crosses.");
        NumericTable t{"Points per test",
                       "test",
                       {"grid", "ok at the last frame", "kept in the field", "mean ZNCC", "min ZNCC"},
                       {},
                       {},
                       6,
                       {}};
        t.column_digits = {4, 4, 4, 5, 4};
        for (const auto& q : quality) {
          t.labels.push_back(q.name);
          t.rows.push_back({double(q.grid), double(q.ok_last), double(q.kept), q.mean_zncc, q.min_zncc});
        }
        s.table(std::move(t));
      }
      {
        Section& s = d.section(kSync, "Synchronisation of the load cell with the camera");
        s.paragraph(
            fmt::format("The clock offset δ (log − camera) from the cross-head and the DIC grip motion over the last "
                        "setting image, the {} hold images and the pull (set, hold, pull); the tare from the log "
                        "before image 0. Truth: δ = {} s, tare {} N.",
                        c.hold, c.clock_offset_s, c.tare_N));
        s.figure(
            fs::path("plots") / "sync.png",
            "Per test: the log's force (tare removed) with the image instants, and the criterion near its optimum.");
        NumericTable t{
            "Clock offset, tare and force per test against the lab record's truth",
            "test",
            {"δ found (s)", "δ error (ms)", "tare (N)", "force RMS error (N)", "force max error (N)", "peak force (N)"},
            {},
            {},
            6,
            {}};
        t.column_digits = {6, 3, 4, 3, 3, 4};
        for (std::size_t i = 0; i < n; ++i) {
          t.labels.push_back(c.tests[i]);
          t.rows.push_back(
              {rows[i].offset, rows[i].error_ms, rows[i].tare, rows[i].force_rms, rows[i].force_max, rows[i].peak});
        }
        s.table(std::move(t));
      }
      {
        Section& s = d.section(kEq9);
        NumericTable t4{"Table 4 (paper §4.3): the identification", "", {"value"}, {}, {}, 5, {}};
        t4.labels = {"objective f", "LM iterations", "evaluations", "wall time (s)", "condition number"};
        t4.rows = {{number(res, "objective")},
                   {number(res, "iterations")},
                   {number(res, "evaluations")},
                   {number(res, "wall_seconds")},
                   {outcome.result.uncertainty.condition_number}};
        s.table(std::move(t4));
        NumericTable t5{"Table 5: eq. 9 error, this chain beside the paper (110 × 110 mm², 14 coefficients)",
                        "force",
                        {"whole", "paper whole", "practical", "paper practical"},
                        {},
                        {},
                        3,
                        {}};
        const char* forces[2] = {"course", "wale"};
        for (int f = 0; f < 2; ++f) {
          const json e = res.contains("eq9") && res["eq9"].contains(forces[f]) ? res["eq9"][forces[f]] : json::object();
          t5.labels.push_back(forces[f]);
          t5.rows.push_back({number(e, "whole"), kPaperWhole[f], number(e, "practical"), kPaperPractical[f]});
        }
        s.table(std::move(t5));
      }
      {
        NumericTable t{"Wall and CPU time per stage of the chain (CPU: user + system, every thread)",
                       "stage",
                       {"wall (s)", "CPU (s)"},
                       {},
                       {},
                       4,
                       {}};
        double wall = 0, cpu = 0;
        for (const auto& x : result.stages) {
          t.labels.push_back(x.name);
          t.rows.push_back({x.wall_s, x.cpu_s});
          wall += x.wall_s, cpu += x.cpu_s;
        }
        t.labels.push_back("chain from images on disk (dic + sync + identify)");
        double chain_wall = 0, chain_cpu = 0;
        for (std::size_t k = 1; k < result.stages.size(); ++k)
          chain_wall += result.stages[k].wall_s, chain_cpu += result.stages[k].cpu_s;
        t.rows.push_back({chain_wall, chain_cpu});
        t.labels.push_back("total, rendering included");
        t.rows.push_back({wall, cpu});
        d.section(kTiming)
            .note("The report stage's own time is in stages.json (it is written after this table).")
            .table(std::move(t));
      }
    });
    result.stages.push_back(st.finish((id / "report.html").string()));
  }
  result.report = out / "identify" / "report.html";
  json stages = json::array();
  for (const auto& x : result.stages) stages.push_back({{"stage", x.name}, {"wall_s", x.wall_s}, {"cpu_s", x.cpu_s}});
  io::write_atomic(out / "stages.json", json{{"stages", stages}, {"converged", result.converged}}.dump(2) + "\n");
  return result;
}

}  // namespace tricot::project
