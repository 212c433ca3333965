// tricot experiment LAB.toml -o DIR (issue 11, docs/theory.md §1 steps i and ii): a lab's raw files — an
// image sequence (or a `tricot dic` output folder), a load-cell log, the specimen and the camera — turned
// into the experiment folder that `tricot identify` reads (experiment_files.hpp):
//
//   DIR/<test>/forces.csv   step, time, load, edge_displacement, edge_force, force_per_width
//   DIR/<test>/field.csv    step, id, x, y, u, v, sigma_u, sigma_v   (quarter model, mm)
//   DIR/<test>/dic/         the DIC run's tables, when the experiment ran it
//   DIR/sync.json           per test: clock_offset_s, method, tare_N, termination, peak correlation,
//                           force_noise_N (the log's spread at rest: written to project.toml as
//                           sigma_edge_force for a single displacement-controlled test)
//   DIR/sync.png            per test: the log's force against time, the image instants, the criterion
//   DIR/project.toml        a skeleton for `tricot identify`: one [[test]] per test
//
// Steps are images 1..n−1 (image 0 is the unloaded reference); a rig test's setting and hold images
// ([[test]] setting_images, hold_images: set, hold, pull) are not steps, and its clock offset comes
// from the pull and the rest before it, its tare from the log before image 0. The grip displacement of the quarter
// model is half the synchronised cross-head travel when the log has one (better than the field's
// estimate), else lab::grip_from_field.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "tricot/dic/sequence.hpp"
#include "tricot/io/config.hpp"
#include "tricot/lab/sync.hpp"
#include "tricot/project/lab_spec.hpp"
#include "tricot/project/log.hpp"

namespace tricot::project {

/// What one test produced.
struct LabTestResult {
  std::string name;
  lab::SyncResult sync;
  int steps = 0;
  int points = 0;
  int outside = 0, incomplete = 0;
  std::vector<double> loads;  ///< forces.csv's load column, step 1 first
  double force_noise_N = 0;   ///< σ of the log's force at rest (sync.json force_noise_N)
  double width_mm = 0;        ///< > 0: the test's own specimen size, written as its [test.mesh] (tracks)
  double free_length_mm = 0;
};

struct LabExperimentResult {
  std::vector<LabTestResult> tests;
};

/// One test's [[test]] table of DIR/project.toml: its name, the `model` lines, the material's orientation
/// from `direction` (wale: material_angle = 0, pull = "wale"; course: 90, "course"), the control and the
/// loads. Throws InputError at `model` when its lines set material_angle or pull themselves.
std::string project_test_table(const LabTestSpec& test, const LabTestResult& result, const ExperimentSpec& e);
/// The same for a [[test]] table read from a file.
std::string project_test_table(const io::Node& test, const LabTestResult& result, const ExperimentSpec& e);

/// Checks the lab file (LabSpec::validate()), runs every test and writes DIR. Throws InputError /
/// FileError naming the file, line and key of what is wrong.
LabExperimentResult run_lab_experiment(const LabSpec& spec, const std::filesystem::path& dir, const Log& log);
/// The same for a lab file read with lab_schema() (`root` from read_config(lab_schema(), file)).
LabExperimentResult run_lab_experiment(const io::Node& root, const std::filesystem::path& dir, const Log& log);

/// Reads a `tricot dic` output folder back: points.csv (with sigma_x, sigma_y), increments.csv when
/// present, and frames.csv (the image of each frame, into `images`). Throws FileError when points.csv is
/// missing, InputError for a malformed table.
dic::SequenceResult read_dic_folder(const std::filesystem::path& dir, std::vector<std::string>* images = nullptr);

/// The image files of a folder, sorted by name (.png, .tif, .tiff, .bmp). FileError when the folder is
/// missing or holds none.
std::vector<std::filesystem::path> list_images(const std::filesystem::path& folder);

}  // namespace tricot::project
