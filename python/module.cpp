// The `tricot` Python module (issue 33, docs/design.md): the pipelines of the verbs and their
// results with NumPy arrays, a law at given deformation gradients, images and fields without copies.
#include <pybind11/pybind11.h>

#include "results.hpp"
#include "spec.hpp"

PYBIND11_MODULE(tricot, m) {
  m.doc() =
      "tricot: identify the large-strain law of a knitted fabric from biaxial tension tests.\n"
      "simulate, identify, synth, experiment, dic take a spec (a dict, or a TOML path) as the CLI's verbs do;\n"
      "Law evaluates a law at given F; Frames, load_image and correlate pass images and fields as NumPy arrays.";
  m.attr("__version__") = "0.1.0";
  tricot::python::register_errors(m);
  tricot::python::bind_verbs(m);
  tricot::python::bind_images(m);
  tricot::python::bind_law(m);
}
