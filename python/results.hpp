// The verbs from Python (issue 33): simulate, identify, synth, experiment and dic, each from a spec (a
// dict or a TOML path) through the project layer's pipeline, the one `tricot VERB` runs; their
// results as objects with NumPy arrays.
#pragma once

#include <pybind11/pybind11.h>

#include "tricot/dic/sequence.hpp"
#include "tricot/project/dic_spec.hpp"

namespace tricot::python {

namespace py = pybind11;

void bind_verbs(py::module_& m);
/// tricot.Frames, tricot.load_image, tricot.correlate (images.cpp).
void bind_images(py::module_& m);
/// tricot.Law (law.cpp).
void bind_law(py::module_& m);
/// The keywords of dic() and correlate() over the spec, as the CLI's flags over the file
/// (project::dic_spec): each one given is named `KEY=` in an error about it.
void apply_dic_keywords(project::DicSpec& d, const py::object& subset, const py::object& step, const std::string& mode,
                        const py::object& roi);
/// The DIC result as a dict of arrays (frames × points); shared by dic() and correlate().
py::dict dic_arrays(const dic::SequenceResult& r);

}  // namespace tricot::python
