// Specs from Python and the exception classes (spec.hpp).
#include "spec.hpp"

#include <toml++/toml.h>

#include <new>
#include <sstream>
#include <system_error>
#include <variant>

#include "tricot/core/error.hpp"

namespace tricot::python {

namespace fs = std::filesystem;

namespace {

// tricot.Error and its subclasses; created once by register_errors (module lifetime: never freed).
PyObject* error_base = nullptr;
PyObject* config_error = nullptr;   // exit code 2
PyObject* file_error = nullptr;     // exit code 3
PyObject* not_converged = nullptr;  // exit code 4

/// The CLI prints one line whatever a message holds (apps/tricot/main.cpp): the same here.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

PyObject* class_of(ExitCode code) {
  switch (code) {
    case ExitCode::input_missing: return file_error;
    case ExitCode::not_converged: return not_converged;
    default: return config_error;
  }
}

/// Sets the Python error: an instance of `cls` with the message and the CLI's exit code, and the
/// file, line and key the message names.
void set_error(PyObject* cls, const std::string& message, ExitCode code, const Location& where,
               const py::object& result = py::none()) {
  py::object exc = py::reinterpret_steal<py::object>(PyObject_CallFunction(cls, "s", message.c_str()));
  if (!exc) return;  // the call set its own error
  exc.attr("exit_code") = static_cast<int>(code);
  exc.attr("file") = where.file;
  exc.attr("line") = where.line;
  exc.attr("key") = where.key;
  exc.attr("result") = result;
  PyErr_SetObject(cls, exc.ptr());
}

[[noreturn]] void config_fail(const std::string& key, const std::string& problem, const std::string& got) {
  throw InputError({"<dict>", 0, key}, problem, got, "a bool, int, float, str, path, list or dict");
}

/// One value of a dict as TOML: a value, a table (dict) or an array (list, tuple, NumPy array).
using Toml = std::variant<bool, std::int64_t, double, std::string, toml::table, toml::array>;

Toml toml_of(const py::handle& v, const std::string& key) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) return v.cast<std::int64_t>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::hasattr(v, "__fspath__")) return path_string(v);
  if (py::isinstance<py::dict>(v)) {
    toml::table t;
    for (auto item : v.cast<py::dict>()) {
      const std::string k = py::str(item.first).cast<std::string>();
      std::visit([&](auto&& node) { t.insert_or_assign(k, std::move(node)); },
                 toml_of(item.second, key.empty() ? k : key + "." + k));
    }
    return t;
  }
  if (py::hasattr(v, "tolist")) return toml_of(v.attr("tolist")(), key);  // NumPy arrays and scalars
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    toml::array a;
    for (const py::handle& e : v) std::visit([&](auto&& node) { a.push_back(std::move(node)); }, toml_of(e, key));
    return a;
  }
  config_fail(key, "a value TOML cannot hold", py::repr(v).cast<std::string>());
}

}  // namespace

std::string path_string(const py::handle& p) {
  if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  return py::module_::import("os").attr("fspath")(p).cast<std::string>();
}

std::string to_toml(const py::handle& spec) {
  if (!py::isinstance<py::dict>(spec)) config_fail("", "a spec must be a dict", py::repr(spec).cast<std::string>());
  const toml::table root = std::get<toml::table>(toml_of(spec, ""));
  std::ostringstream os;
  os << root << "\n";
  return os.str();
}

LoadedSpec load_spec(const py::handle& spec, const io::SectionSpec& schema, const py::handle& base) {
  const fs::path folder = base.is_none() ? fs::path() : fs::path(path_string(base));
  if (spec.is_none()) return {io::default_config(schema), folder, "<defaults>"};
  if (py::isinstance<py::dict>(spec)) {
    const std::string text = to_toml(spec);
    // The name stands for the file: its folder is where relative paths are taken from (lab files).
    const std::string name = folder.empty() ? "<dict>" : (folder / "<dict>").string();
    return {io::parse_config(schema, text, name), folder, name};
  }
  const std::string file = path_string(spec);
  return {io::read_config(schema, file), fs::path(file).parent_path(), file};
}

void check_out_dir(const std::string& dir) {
  // As apps/tricot/out_dir.cpp's check, the keyword `out` in place of the flag -o.
  if (dir.empty())
    throw InputError({"out", 0, ""}, "empty output folder", "''", "a folder path (use . for this folder)");
  std::error_code ec;
  for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st))
        throw FileError({p.string(), 0, ""}, p == fs::path(dir) ? "the output folder is a file" : "not a folder", "",
                        "a folder, or a path that does not exist yet");
      break;
    }
    if (p == p.parent_path()) break;
  }
}

void raise_not_converged(const std::string& message, const py::object& result) {
  set_error(not_converged, message, ExitCode::not_converged, {}, result);
  throw py::error_already_set();
}

void register_errors(py::module_& m) {
  error_base = PyErr_NewExceptionWithDoc(
      "tricot.Error",
      "An error of tricot: str(e) is the CLI's one-line message (FILE:LINE: KEY: what is wrong (got VALUE, "
      "expected RANGE)); e.exit_code is the CLI's exit code; e.file, e.line, e.key where it is.",
      PyExc_Exception, nullptr);
  config_error = PyErr_NewExceptionWithDoc(
      "tricot.ConfigError", "Bad spec, config, argument or input value (exit code 2).", error_base, nullptr);
  file_error = PyErr_NewExceptionWithDoc(
      "tricot.InputFileError", "An input file or folder missing or unreadable (exit code 3).", error_base, nullptr);
  not_converged = PyErr_NewExceptionWithDoc(
      "tricot.NotConvergedError", "The run finished but did not converge (exit code 4); e.result holds what it found.",
      error_base, nullptr);
  m.add_object("Error", py::handle(error_base));
  m.add_object("ConfigError", py::handle(config_error));
  m.add_object("InputFileError", py::handle(file_error));
  m.add_object("NotConvergedError", py::handle(not_converged));

  // The CLI's catch blocks (apps/tricot/main.cpp), each error as the same one line and exit code.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      set_error(class_of(e.exit_code()), one_line(e.what()), e.exit_code(), e.where());
    } catch (const fs::filesystem_error& e) {
      const std::string file = e.path1().empty() ? "filesystem" : e.path1().string();
      set_error(file_error, one_line(format_error({file, 0, ""}, e.code().message(), {}, {})), ExitCode::input_missing,
                {file, 0, ""});
    } catch (const std::system_error& e) {
      set_error(config_error, one_line(format_error({"system", 0, ""}, e.what(), {}, "fewer threads or more memory")),
                ExitCode::usage, {"system", 0, ""});
    }
  });
}

}  // namespace tricot::python
