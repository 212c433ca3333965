// A small uniaxial Mooney–Rivlin case for the synth and identify CLI tests: a 20 × 60 mm strip,
// force-controlled in 10 steps to λ ≈ 1.6, 3 × 8 Q8 elements (~0.2 s per FE run with
// sensitivities), the truth fem::paper_mooney_rivlin_terms().
#pragma once

#include <fmt/format.h>

#include <filesystem>
#include <string>

#include "tricot/io/files.hpp"

namespace tricot::test {

/// The case sections shared by the experiment and the project (the same mesh: a unit test may
/// commit the inverse crime to check that the pipeline recovers the truth to round-off).
inline std::string small_case(const std::string& values) {
  return fmt::format(R"([mesh]
width = 20.0
height = 60.0
element = "Q8"
nx = 3
ny = 8

[law]
type = "mooney_rivlin"
[law.mooney_rivlin]
terms = ["C10", "C20", "C21", "C03"]
values = {}

[[test]]
name = "tension"
kind = "uniaxial"
control = "force"
load_max = 5.0
steps = 10
)",
                     values);
}

inline const char* kTruthValues = "[0.1, -0.025, 0.015, 0.01]";

/// An experiment file: the small case with the truth and a [synth] table.
inline std::string small_experiment(const std::string& synth = "nx = 3\nny = 5\n") {
  return small_case(kTruthValues) + "\n[synth]\n" + synth;
}

/// A project file identifying C10, C20, C21, C03 from `dir`, starting at truth × 0.5.
inline std::string small_project(const std::string& dir, const std::string& extra = {},
                                 const std::string& parameters =
                                     "[[parameter]]\nname = \"C10\"\n"
                                     "[[parameter]]\nname = \"C20\"\n"
                                     "[[parameter]]\nname = \"C21\"\n"
                                     "[[parameter]]\nname = \"C03\"\n") {
  return small_case("[0.05, -0.0125, 0.0075, 0.005]") + "\n[experiment]\ndir = \"" + dir + "\"\n\n" + parameters +
         "\n" + extra;
}

inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& text) {
  io::write_atomic(path, text);
  return path;
}

}  // namespace tricot::test
