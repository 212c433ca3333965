// NumPy arrays over C++ buffers without copies (issue 33): an array adopts a buffer (its base object
// is a capsule that frees it), or views one whose owner it keeps alive.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <filesystem>
#include <vector>

namespace tricot::python {

namespace py = pybind11;

/// A C-contiguous array of `shape` over `v`'s buffer, moved (not copied) into the array's base.
template <class T>
py::array_t<T> adopt(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(v));
  py::capsule base(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), owner->data(), base);
}

/// A CSV table (io::read_csv) as a dict: column name → 1-D float64 array.
py::dict table_dict(const std::filesystem::path& csv);

}  // namespace tricot::python
