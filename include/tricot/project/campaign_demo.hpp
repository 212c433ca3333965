// tricot demo: the whole chain of the paper's Fig. 1 on the §4 campaign of the reference knit
// (issue 13): camera images and load-cell logs of the 110 × 110 mm² series (tricot synth), DIC of
// every test (tricot dic), the lab files turned into an experiment (tricot experiment:
// synchronisation, specimen coordinates), the `paper14` identification (tricot identify) and the lab
// report. Each stage is the verb's own pipeline function, run in this process, on the campaign's files
// in examples/knit-campaign/demo (built into tricot, examples.hpp), which it writes to DIR first.
//
//   DIR/experiment.toml     the synthetic campaign (tricot synth); DIR/raw/ its output: per test the
//                           FE data (forces.csv, field.csv), images/ and lab/ (load.txt, camera.csv)
//   DIR/dic.toml, DIR/dic/<test>/        the DIC runs (points.csv, frames.csv)
//   DIR/lab.toml, DIR/project-template.toml, DIR/experiment/   tricot experiment's input and output
//   DIR/identify/           tricot identify's output: result.json, report.html, report.json, plots/
//   DIR/stages.json         wall and CPU seconds per stage
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tricot/project/log.hpp"

namespace tricot::project {

/// Which campaign the demo runs.
struct CampaignDemoOptions {
  /// The reduced chain the browser test runs: two tests (wale 40 %, course 30 %), 6 pull steps, a
  /// 12 × 10 generating mesh, 320 × 256 px images, two LM iterations without the stability test
  /// (examples/knit-campaign/demo/small).
  bool small = false;
};

/// The folder under examples/ of the campaign's files (the user can rerun any stage by hand with the
/// verbs): experiment.toml (tricot synth), dic.toml (tricot dic), lab.toml (tricot experiment) and
/// project-template.toml (its [experiment] project_template).
std::string campaign_example(const CampaignDemoOptions& o);

/// Wall and CPU (user + sys, every thread) seconds of one stage.
struct StageTime {
  std::string name;
  double wall_s = 0, cpu_s = 0;
};

struct CampaignDemoResult {
  bool converged = false;         ///< the identification converged
  std::vector<StageTime> stages;  ///< render, dic, sync, identification, report
  std::filesystem::path report;   ///< DIR/identify/report.html
};

/// Runs the chain into `out` and adds the chain's sections to the identification's report: the DIC
/// quality per test, the synchronisation against the lab record's truth, Tables 4 and 5 beside the
/// paper's values, the wall time per stage. One progress report per stage ("1/5 render", ...); the
/// engines' own lines go to the reporter's log. Throws what the verbs throw.
CampaignDemoResult run_campaign_demo(const CampaignDemoOptions& options, const std::filesystem::path& out,
                                     const Log& log);

}  // namespace tricot::project
