// Images in and out of NumPy without copies (issue 33). tricot.Frames holds the C++ images
// (std::vector<image::Image>, what dic::track_sequence reads) and hands out each frame as a float32
// NumPy array over the frame's own pixels (its base is the Frames object): a script writes a frame in
// place and correlate() reads those very pixels. tricot.load_image returns an array that adopts the
// decoded image's buffer. correlate's fields are arrays that adopt the buffers they were built in.
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "results.hpp"
#include "run.hpp"
#include "spec.hpp"
#include "tricot/core/error.hpp"
#include "tricot/dic/icgn.hpp"
#include "tricot/dic/sequence.hpp"
#include "tricot/image/image.hpp"
#include "tricot/project/dic_spec.hpp"

namespace tricot::python {

namespace {

/// The frames of a sequence, frame 0 the reference.
struct Frames {
  std::vector<image::Image> images;

  image::Image& at(py::ssize_t i) {
    if (i < 0) i += py::ssize_t(images.size());
    if (i < 0 || i >= py::ssize_t(images.size())) throw py::index_error("frame index out of range");
    return images[std::size_t(i)];
  }
};

/// The frame `img` as a (height, width) float32 array over its pixels; `owner` keeps them alive.
py::array_t<float> view(image::Image& img, const py::handle& owner) {
  return py::array_t<float>({py::ssize_t(img.height), py::ssize_t(img.width)}, img.pixels.data(), owner);
}

/// A 2-D array's values as a new image (the one copy, for a frame built from an existing array).
image::Image image_of(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, double full_scale) {
  if (a.ndim() != 2)
    throw InputError({"frames", 0, ""}, "an image must be a 2-D array", std::to_string(a.ndim()) + " dimensions",
                     "(height, width)");
  image::Image img(int(a.shape(1)), int(a.shape(0)), 0.0f, full_scale);
  std::copy(a.data(), a.data() + a.size(), img.pixels.begin());
  return img;
}

py::object correlate(Frames& frames, const py::object& spec, const py::object& subset, const py::object& step,
                     const std::string& mode, const py::object& roi, const py::object& base,
                     const py::object& progress) {
  const LoadedSpec s = load_spec(spec, project::dic_schema(), base);
  if (frames.images.size() < 2)
    throw InputError({"frames", 0, ""}, "a sequence needs a reference and a frame",
                     std::to_string(frames.images.size()) + " frames", ">= 2");
  project::DicSpec d = project::DicSpec::from_config(s.root, s.base);
  apply_dic_keywords(d, subset, step, mode, roi);
  for (const image::Image& img : frames.images) image::require_same_size(frames.images.front(), img, "frames");
  const project::DicSettings settings = d.settings(frames.images.front());
  Runner runner(progress, py::none());
  const Reporter reporter = runner.log().reporter();
  // The frames' own pixels go to the engine: the vector is passed by reference, nothing is copied.
  const dic::SequenceResult r =
      runner.run([&] { return dic::track_sequence(frames.images, settings.roi, settings.sequence, reporter); });
  py::dict fields = dic_arrays(r);
  fields["termination"] = r.termination == dic::SequenceTermination::completed ? "completed" : "all_lost";
  fields["message"] = r.message;
  return fields;
}

}  // namespace

void bind_images(py::module_& m) {
  using namespace py::literals;
  py::class_<Frames>(m, "Frames",
                     "An image sequence held by tricot (frame 0 the reference). frames[i] is a float32 (height, width) "
                     "array over frame i's own pixels: writing it writes the frame, and correlate() reads it in place.")
      .def(py::init([](py::ssize_t count, int height, int width, double full_scale) {
             if (count < 0 || height <= 0 || width <= 0)
               throw InputError({"Frames", 0, ""}, "a sequence size must be positive",
                                std::to_string(count) + " × " + std::to_string(height) + " × " + std::to_string(width),
                                "count >= 0, height and width > 0");
             Frames f;
             f.images.assign(std::size_t(count), image::Image(width, height, 0.0f, full_scale));
             return f;
           }),
           "count"_a, "height"_a, "width"_a, "full_scale"_a = 1.0,
           "count frames of height × width zeros, to fill in place")
      .def(py::init([](const py::list& arrays, double full_scale) {
             Frames f;
             for (const py::handle& a : arrays)
               f.images.push_back(
                   image_of(py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a), full_scale));
             return f;
           }),
           "arrays"_a, "full_scale"_a = 1.0,
           "frames copied once from 2-D arrays (fill Frames(count, h, w) in place to copy none)")
      .def_static(
          "load",
          [](const py::list& paths) {
            Frames f;
            for (const py::handle& p : paths) f.images.push_back(image::load_image(path_string(p)).image);
            if (!f.images.empty())
              for (std::size_t i = 1; i < f.images.size(); ++i)
                image::require_same_size(f.images.front(), f.images[i], path_string(paths[i]));
            return f;
          },
          "paths"_a, "image files (8/16-bit PNG, TIFF, BMP) decoded into tricot's frames")
      .def("__len__", [](const Frames& f) { return f.images.size(); })
      .def(
          "__getitem__", [](py::object self, py::ssize_t i) { return view(self.cast<Frames&>().at(i), self); }, "i"_a)
      .def(
          "append",
          [](py::object self, int height, int width) {
            Frames& f = self.cast<Frames&>();
            f.images.emplace_back(width, height, 0.0f, f.images.empty() ? 1.0 : f.images.front().full_scale);
            return view(f.images.back(), self);
          },
          "height"_a, "width"_a, "adds a frame of zeros and returns it as an array to fill")
      .def(
          "address", [](Frames& f, py::ssize_t i) { return reinterpret_cast<std::uintptr_t>(f.at(i).pixels.data()); },
          "i"_a, "the address of frame i's pixels in tricot's memory (equal to its array's data pointer: no copy)")
      .def(
          "sum",
          [](Frames& f, py::ssize_t i) {
            double s = 0;
            for (float p : f.at(i).pixels) s += p;
            return s;
          },
          "i"_a, "the sum of frame i's pixels, read by C++");
  m.def(
      "load_image",
      [](const py::object& path) {
        image::LoadedImage loaded = image::load_image(path_string(path));
        const py::ssize_t h = loaded.image.height, w = loaded.image.width;
        return adopt(std::move(loaded.image.pixels), {h, w});
      },
      "path"_a,
      "An 8/16-bit gray PNG, TIFF or BMP as a float32 (height, width) array of its gray levels, over the decoded "
      "buffer.");
  m.def("correlate", &correlate, "frames"_a, "spec"_a = py::none(), py::kw_only(), "subset"_a = py::none(),
        "step"_a = py::none(), "mode"_a = "", "roi"_a = py::none(), "base"_a = py::none(), "progress"_a = py::none(),
        "DIC over a Frames sequence in memory (tricot dic's engine and [dic]/[strain] spec, no files): a dict of "
        "arrays (frames × points: x, y, u, v, zncc, status, exx, eyy, exy, sigma_u, sigma_v; points: x0, y0).");
  py::list names;
  for (int s = 0; s <= static_cast<int>(dic::PointStatus::lost); ++s)
    names.append(dic::to_string(static_cast<dic::PointStatus>(s)));
  m.attr("status_names") = names;
}

}  // namespace tricot::python
