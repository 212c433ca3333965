// Long runs from Python (issue 33): the GIL is released while a pipeline runs; its progress reports
// and summary lines come back through Python callbacks (or stderr), and Ctrl-C stops it.
//
// Ctrl-C: Python's own SIGINT handler only sets a flag while C++ runs. At each progress report the
// GIL is taken back and PyErr_CheckSignals runs the handler; a KeyboardInterrupt it raises (or any
// exception a callback raises) is kept, and the run is stopped by a C++ exception at the first report
// made on the calling thread outside a parallel region (never inside an OpenMP team, where an
// exception cannot leave). An identification reports once per LM iteration, right after its
// checkpoint is written: stopped there, its staging folder holds that checkpoint, and
// identify(..., resume=True) goes on from it to the answer of an uninterrupted run.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <memory>
#include <optional>
#include <thread>

#include "tricot/project/log.hpp"

namespace tricot::python {

namespace py = pybind11;

class Runner {
 public:
  /// `progress`: None, True (one line per report on stderr) or a callable (stage, done, total, detail);
  /// `log`: None, True (stderr) or a callable (line) for the pipeline's summary lines.
  Runner(py::object progress, py::object log);
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  /// The pipeline's Log: its reports and lines come here.
  project::Log log();

  /// Runs `f` without the GIL. A Python error raised by a callback or by Ctrl-C during the run is
  /// raised here (also when the run finished before it could be stopped).
  template <class F>
  auto run(F&& f) -> decltype(f()) {
    std::optional<decltype(f())> result;
    try {
      py::gil_scoped_release release;
      result.emplace(f());
    } catch (const Stopped&) {  // a kept Python error, raised below
    }
    raise_pending();
    return std::move(*result);
  }
  /// Raises the kept Python error, if any (needs the GIL: call after run()).
  void raise_pending();

 private:
  struct Stopped {};
  void on_progress(const Progress& p);
  void on_line(const std::string& line);
  void keep_error();
  void stop_if_asked();

  py::object progress_, log_;
  std::thread::id caller_;
  std::atomic<bool> stopping_{false};
  std::unique_ptr<py::error_already_set> error_;
};

}  // namespace tricot::python
