// Long runs from Python: callbacks, the GIL and Ctrl-C (run.hpp).
#include "run.hpp"

#include <omp.h>

#include <cstdio>

namespace tricot::python {

Runner::Runner(py::object progress, py::object log)
    : progress_(std::move(progress)), log_(std::move(log)), caller_(std::this_thread::get_id()) {}

Runner::~Runner() = default;

project::Log Runner::log() {
  Reporter reporter;
  reporter.progress = [this](const Progress& p) { on_progress(p); };
  return project::Log(reporter, [this](const std::string& line) { on_line(line); });
}

void Runner::on_progress(const Progress& p) {
  if (!stopping_) {
    py::gil_scoped_acquire gil;
    try {
      if (py::isinstance<py::bool_>(progress_)) {
        if (progress_.cast<bool>())
          std::fprintf(stderr, "%s: %zu/%zu %s\n", p.stage.c_str(), p.done, p.total, p.detail.c_str());
      } else if (!progress_.is_none()) {
        progress_(p.stage, p.done, p.total, p.detail);
      }
      // Python's SIGINT handler runs here, on the main thread: KeyboardInterrupt on Ctrl-C.
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (py::error_already_set& e) {
      error_ = std::make_unique<py::error_already_set>(std::move(e));
      stopping_ = true;
    }
  }
  stop_if_asked();
}

void Runner::on_line(const std::string& line) {
  if (stopping_ || log_.is_none()) return;
  py::gil_scoped_acquire gil;
  try {
    if (py::isinstance<py::bool_>(log_)) {
      if (log_.cast<bool>()) std::fprintf(stderr, "%s\n", line.c_str());
    } else {
      log_(line);
    }
  } catch (py::error_already_set& e) {
    error_ = std::make_unique<py::error_already_set>(std::move(e));
    stopping_ = true;
  }
}

void Runner::stop_if_asked() {
  // Only where an exception may leave: the calling thread, outside an OpenMP team.
  if (stopping_ && std::this_thread::get_id() == caller_ && !omp_in_parallel()) throw Stopped{};
}

void Runner::raise_pending() {
  if (!error_) return;
  std::unique_ptr<py::error_already_set> e = std::move(error_);
  e->restore();
  throw py::error_already_set();
}

}  // namespace tricot::python
