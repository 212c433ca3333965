// tricot dic [CONFIG.toml] [flags] -o DIR IMAGE...: digital image correlation over an image sequence
// (project/dic_run.hpp): flags over the config, the run, then warnings and the exit code.
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "console.hpp"
#include "tricot/project/dic_run.hpp"
#include "verbs.hpp"

namespace tricot::cli {

namespace {

namespace fs = std::filesystem;

struct DicArgs {
  std::vector<std::string> inputs;  ///< [CONFIG.toml] IMAGE...
  std::string out_dir;
  project::DicFlags flags;
  int subset = 0, step = 0;
  CLI::Option *subset_given = nullptr, *step_given = nullptr;
  bool verbose = false, quiet = false, resume = false;
};

constexpr const char* kFooter = R"(
The first IMAGE is the reference (frame 0); give the others in time order (8- or 16-bit TIFF, PNG,
BMP; colour is converted to gray with a warning). A square subset of --subset px sits on every grid
point (--step px apart) inside the region of interest; inverse-compositional Gauss-Newton (ZNSSD,
bicubic B-splines) matches it in every image, starting from FFT cross-correlation at a seed and
spreading to the neighbours with the highest correlation first. Each subset is matched to first
order and kept at second order where an F-test says the extra terms pay (dic.order = "auto", the
default; "first" or "second" to force one).

Modes: incremental (default) correlates each image with the previous one and follows the material
points, which survives strains above 100 %; reference correlates every image with the first; auto
keeps the reference until the correlation drops, then moves it to the previous image.

Writes:
  DIR/points.csv    frame,id,x0,y0,x,y,u,v,zncc,status,exx,eyy,exy,sigma_x,sigma_y: one row per point and frame.
                    px, x to the right and y down; (x0, y0) in the reference, (x, y) in the frame;
                    status `ok` or why not (no_texture, low_correlation, out_of_image, lost, ...);
                    Green-Lagrange strains (a plane fit over [strain] window points). Cells
                    without a value are empty.
  DIR/frames.csv    frame, image, reference frame, points ok, mean ZNCC, seconds, vsg_px: the strains'
                    virtual strain gauge, (window - 1) x step + subset px.
  DIR/overlays/frame_NNNN.png   displacement, strain and ZNCC maps drawn over each image.
  DIR/fields/frame_NNNN.vtu     u, v, strains, ZNCC and status on the grid (compressed binary VTK;
                                field data vsg_px);
  DIR/fields.pvd                the series: open it in ParaView ([output] fields, fields_every).
  DIR/increments.csv            with [output] increments = true: fixed-point incremental fields.
  DIR/specimen.csv              with [physical] mm_per_px > 0: the same in specimen mm.
The files grow frame by frame in DIR/.tricot-dic/ and replace DIR's earlier ones at the end; memory
does not grow with the number of frames. A killed run goes on from its last complete frame with
--resume (same config, flags and images).

Examples:
  tricot dic -o out/dic frames/img_*.tif
  tricot dic --subset 41 --step 20 --roi 200,100,1800,900 -o out/dic ref.tif def1.tif def2.tif
  tricot dic --print-config > dic.toml     # every key, commented; edit, then:
  tricot dic dic.toml --mode auto -o out/dic frames/*.png
  tricot dic dic.toml --mode auto -o out/dic frames/*.png --resume    # after a crash or kill

Exit codes: 0 ok, 2 bad command line or config, 3 an image or the config is missing or unreadable
(or an image's size differs from the reference), 4 every point was lost (results are still written).
)";

bool is_config(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".toml";
}

ExitCode run_dic(const DicArgs& a) {
  std::string config;
  std::vector<std::string> images;
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    if (i == 0 && is_config(a.inputs[i])) config = a.inputs[i];
    else images.push_back(a.inputs[i]);
  }
  if (images.empty())
    throw InputError({"command line", 0, "IMAGE"}, "no image given", {}, "the reference image, then the frames");
  const project::DicSpec spec = project::dic_spec(config, a.flags);
  Console console(a.verbose, a.quiet);
  console.line_per_step("dic");  // off a terminal, one line per correlated frame
  const project::Log log = console.log();
  project::DicRunOptions options;
  options.resume = a.resume;
  options.keep_frames = false;  // streamed: the files hold the frames
  const project::DicRun run = project::run_dic(spec, images, a.out_dir, log, options);
  const dic::SequenceResult& r = run.result;
  const std::vector<std::string>& warnings = run.warnings;
  if (!warnings.empty())
    std::fprintf(stderr, "tricot: warning: %s%s\n", warnings.front().c_str(),
                 warnings.size() > 1 ? fmt::format(" (and {} more images)", warnings.size() - 1).c_str() : "");
  if (r.termination == dic::SequenceTermination::all_lost) {
    const int lost_at = std::max(run.lost_at, 0);
    std::fprintf(stderr, "tricot: error: %s: every point was lost (no point ok from frame %d on; see frames.csv)\n",
                 images[lost_at].c_str(), lost_at);
    return ExitCode::not_converged;
  }
  return ExitCode::ok;
}

}  // namespace

Runner add_dic(CLI::App& app) {
  auto args = std::make_shared<DicArgs>();
  CLI::App* cmd =
      app.add_subcommand("dic", "Digital image correlation over an image sequence (first image = reference)");
  cmd->footer(kFooter);
  cmd->add_option("inputs", args->inputs,
                  "[CONFIG.toml] IMAGE...: an optional config (see --print-config), then the images")
      ->required();
  cmd->add_option("-o,--out", args->out_dir, "Output folder")->required();
  args->subset_given = cmd->add_option("--subset", args->subset,
                                       "Subset size in px, odd, 7 to 301 (overrides dic.subset_size; default 31)");
  args->step_given = cmd->add_option("--step", args->step, "Grid step in px (overrides dic.step; default 10)")
                         ->check(CLI::Range(1, 1000));
  cmd->add_option("--mode", args->flags.mode,
                  "incremental, reference or auto (overrides dic.mode; default incremental)")
      ->check(CLI::IsMember({"incremental", "reference", "auto"}));
  cmd->add_option("--roi", args->flags.roi,
                  "Region of interest X0,Y0,X1,Y1 in px (overrides dic.roi; default the whole image)");
  cmd->add_flag("-v,--verbose", args->verbose, "Log every frame (points ok, mean ZNCC, seeds, reference updates)");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  cmd->add_flag(
      "--resume", args->resume,
      "Go on with a killed run into the same -o folder from its last complete frame (same config, flags, images)");
  add_print_config(cmd, project::dic_schema);
  return [args]() {
    check_out_dir(args->out_dir);
    if (args->subset_given->count()) args->flags.subset = args->subset;
    if (args->step_given->count()) args->flags.step = args->step;
    return run_dic(*args);
  };
}

}  // namespace tricot::cli
