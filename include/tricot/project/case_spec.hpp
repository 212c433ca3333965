// The case file of `tricot simulate` (and the shared part of synth's and identify's files): the
// specimen's mesh, the material law, the solver and the list of tests (THEORY §5–§6). Each table is a
// function returning its io::SectionSpec, so that another verb's schema can add its own tables beside
// them; the builders turn validated tables into the engines' value types. Every check that spans keys
// goes through io::Node::fail, so errors read `FILE:LINE: KEY: problem (got V, expected R)`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tricot/fem/law.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"

namespace tricot::project {

/// `[mesh]`: the specimen (full size, mm) and its structured quarter mesh.
io::SectionSpec mesh_section();
/// `[law]`: `type` picks one of the sub-tables `[law.mooney_rivlin]`, `[law.neo_hookean]`,
/// `[law.corotational]`, `[law.response_surface]`, `[law.reference_fabric]`; the others are ignored,
/// so a file may keep several laws and switch by `type` alone.
io::SectionSpec law_section();
/// `[solver]`: Newton tolerances, line search, cutbacks (fem::SolveOptions).
io::SectionSpec solver_section();
/// `[[test]]`: one test (kind, material angle, grip, side edge, step list, optional `[test.mesh]`).
io::SectionSpec test_section();
/// The whole case file: [mesh], [law], [solver] and [[test]].
io::SectionSpec case_schema();

/// What a test does (`kind` in `[[test]]`).
enum class TestKind {
  uniaxial,      ///< grip on top, side edge free (clamped grip by default: a non-uniform field)
  biaxial,       ///< grip on top, side edge on a guide (the paper's biaxial-induced test)
  homogeneous,   ///< sliding grip, side free or guided: a uniform field (closed-form checks)
  simple_shear,  ///< no FE solve: the law at F = [[1, γ], [0, 1]] for γ in the step list (THEORY §4)
};
TestKind test_kind(const io::Node& test);

/// The mesh of a test: `[mesh]`, with the keys that `[test.mesh]` sets (non-zero, non-empty) in place.
fem::MeshOptions build_mesh_options(const io::Node& mesh, const io::Node* test_mesh = nullptr);
/// A test model from its `[[test]]` table and the case's `[mesh]`. For simple_shear: a one-element
/// unit square (type as in the mesh) whose loads are the γ values. Throws InputError located in the
/// file for every inconsistency (fem's own validate() included).
fem::TestModel build_test(const io::Node& test, const io::Node& mesh);
/// The law of `[law]`. Throws InputError located at the offending key.
std::unique_ptr<fem::Law> build_law(const io::Node& law);
fem::SolveOptions build_solver(const io::Node& solver);

/// Checks the list of tests of a case: at least one, names unique and usable as folder names.
void check_tests(const io::Node& root);

}  // namespace tricot::project
