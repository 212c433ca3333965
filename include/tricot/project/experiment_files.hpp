// The experiment on disk: what `tricot synth` writes and `tricot identify` reads (docs/design.md
// "Outputs"). One folder per experiment, one sub-folder per test:
//
//   DIR/<test>/forces.csv   step, load, edge_displacement, edge_force        (one row per step)
//   DIR/<test>/field.csv    step, id, x, y, u, v                             (optional)
//   DIR/truth.json          how a synthetic experiment was made (synth only)
//
// Steps are numbered 1..K as in forces.csv (the unloaded reference is not a step). Lengths are mm in
// the model's coordinates (quarter specimen, x from the vertical axis of symmetry, y from the
// horizontal one), forces N for the full specimen. field.csv holds either cumulative displacements of
// material points (x, y = reference position) or incremental ones at fixed image points (x, y = the
// fixed position; u, v = displacement since the previous step); the project file says which
// (docs/theory.md §7). In forces.csv a missing edge_displacement or edge_force column means "not measured".
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tricot/fem/mesh.hpp"
#include "tricot/ident/experiment.hpp"

namespace tricot::project {

inline constexpr const char* kForcesFile = "forces.csv";
inline constexpr const char* kFieldFile = "field.csv";
inline constexpr const char* kTruthFile = "truth.json";

/// Writes DIR/<d.name>/forces.csv and, when d has field data, DIR/<d.name>/field.csv (atomic, full
/// precision). A measured list that is empty is left out of forces.csv.
void write_test_data(const std::filesystem::path& dir, const ident::TestData& d);

/// Reads DIR/<name>/forces.csv and, when it exists, DIR/<name>/field.csv, the field being of `kind`.
/// σ is left at 0 (per-point sigma_u, sigma_v columns of field.csv, when present, are read). Throws FileError (exit 3)
/// when the folder or forces.csv is missing, InputError with FILE:LINE: COLUMN for a bad cell (NaN included), a step
/// out of order or out of range, a duplicate (step, id), a point missing at some step, or a point whose x, y change
/// between steps.
ident::TestData read_test_data(const std::filesystem::path& dir, const std::string& name, ident::FieldKind kind);

/// read_test_data for every name, then Experiment::validate(). FileError when DIR is missing.
ident::Experiment read_experiment(const std::filesystem::path& dir, const std::vector<std::string>& names,
                                  ident::FieldKind kind);

/// How a synthetic experiment was made: DIR/truth.json.
struct Truth {
  struct Test {
    std::string name;
    std::string control;    ///< "displacement" or "force"
    fem::MeshOptions mesh;  ///< the generating mesh (quarter: width, height are half the specimen's)
    int dofs = 0;
    int steps = 0;
    int points = 0;          ///< field points written (0 = no field.csv)
    int dropped_points = 0;  ///< grid points left out (incremental: they left the specimen)
    ident::Sigma sigma;      ///< noise σ actually added (absolute, in the data's units)
  };
  std::string law;                 ///< fem::Law::name()
  std::vector<std::string> names;  ///< coefficient names
  std::vector<double> values;      ///< their true values
  double noise_relative = 0;       ///< σ as a fraction of each group's RMS (0 = absolute σ given)
  std::uint64_t seed = 0;
  ident::FieldKind field_kind = ident::FieldKind::cumulative;
  std::vector<Test> tests;

  const Test* find(const std::string& name) const;
  /// The true value of a coefficient, or nullopt.
  std::optional<double> value(const std::string& name) const;
};

void write_truth(const std::filesystem::path& dir, const Truth& truth);
/// DIR/truth.json, or nullopt when there is none. InputError (naming the file and key) when malformed.
std::optional<Truth> read_truth(const std::filesystem::path& dir);

}  // namespace tricot::project
