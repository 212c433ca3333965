// tricot synth: a synthetic experiment from FE runs with a known law (issue 4, docs/design.md).
// Exposed so that `tricot demo` generates its data through the same code.
#pragma once

#include <filesystem>

#include "tricot/project/log.hpp"
#include "tricot/project/experiment_files.hpp"
#include "tricot/io/config.hpp"

namespace tricot::project {

/// The experiment file: the case sections ([mesh], [law], [solver], [[test]]) and [synth].
io::SectionSpec synth_schema();

/// Runs every test of a validated experiment file with its law, takes the grip's displacement and
/// force and the field at a grid of points, adds Gaussian noise (fixed seed) and writes the
/// experiment to `dir` (experiment_files.hpp), truth.json included. Prints one line per test.
/// Throws InputError for a bad file; a test that does not converge with the true law throws an
/// InputError whose exit code is 4 (the data would be incomplete), naming the test and step.
Truth synthesize(const io::Node& root, const std::filesystem::path& dir, const Log& log);

}  // namespace tricot::project
