// A law evaluated at given deformation gradients from Python (issue 33): the [law] table of a case
// (LawSpec, the one the CLI reads) and fem::Law::evaluate at each F, for users' own scripts.
#include <string>

#include "arrays.hpp"
#include "results.hpp"
#include "spec.hpp"
#include "tricot/core/error.hpp"
#include "tricot/fem/law.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/identification_spec.hpp"
#include "tricot/project/synthesis.hpp"

namespace tricot::python {

namespace {

struct PyLaw {
  std::unique_ptr<fem::Law> law;
};

/// The law of a spec: a dict holding [law] (a whole case or project), or the [law] table itself, or
/// a case, project or experiment file.
PyLaw make_law(const py::object& spec, const py::object& base) {
  if (py::isinstance<py::dict>(spec)) {
    py::dict d = spec.cast<py::dict>();
    py::dict whole;
    if (d.contains("law")) whole["law"] = d["law"];
    else whole["law"] = d;
    const LoadedSpec s = load_spec(whole, project::case_schema(), base);
    return {project::LawSpec::from_config(s.root.section("law")).law()};
  }
  // A file: a case, a project or a synth experiment ([synth]); the case schema's error if none reads it.
  try {
    const LoadedSpec s = load_spec(spec, project::case_schema(), base);
    return {project::LawSpec::from_config(s.root.section("law")).law()};
  } catch (const FileError&) {
    throw;
  } catch (const InputError& first) {
    for (const auto& schema : {project::identify_schema, project::synth_schema}) {
      try {
        const LoadedSpec s = load_spec(spec, schema(), base);
        return {project::LawSpec::from_config(s.root.section("law")).law()};
      } catch (const InputError&) {}
    }
    throw;
  }
}

/// (n, 2, 2) float64 from (2, 2) or (n, 2, 2).
py::array_t<double, py::array::c_style | py::array::forcecast> tensors(const py::object& a, const char* what) {
  auto t = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!t) throw py::error_already_set();
  if (t.ndim() == 2 && t.shape(0) == 2 && t.shape(1) == 2)
    t = t.reshape({py::ssize_t(1), py::ssize_t(2), py::ssize_t(2)});
  if (t.ndim() != 3 || t.shape(1) != 2 || t.shape(2) != 2)
    throw InputError({what, 0, ""}, "not 2 × 2 tensors", py::str(a.attr("shape")).cast<std::string>(),
                     "(2, 2) or (n, 2, 2)");
  return t;
}

py::tuple evaluate(const PyLaw& self, const py::object& F_in, const py::object& Q_in, const std::string& tangent) {
  if (tangent != "tensor" && tangent != "matrix" && tangent != "none")
    throw InputError({"tangent", 0, ""}, "unknown tangent layout", tangent, "tensor, matrix or none");
  const auto F = tensors(F_in, "F");
  const py::ssize_t n = F.shape(0);
  py::array_t<double, py::array::c_style | py::array::forcecast> Q;
  const bool has_Q = !Q_in.is_none();  // (a default array_t is an empty array, not a null handle)
  if (has_Q) {
    Q = tensors(Q_in, "Q");
    if (Q.shape(0) != 1 && Q.shape(0) != n)
      throw InputError({"Q", 0, ""}, "one material frame, or one per F", std::to_string(Q.shape(0)),
                       "1 or " + std::to_string(n));
  }
  std::vector<double> P(std::size_t(n) * 4), A(tangent == "none" ? 0 : std::size_t(n) * 16);
  std::vector<double> lambda3(static_cast<std::size_t>(n));
  {
    py::gil_scoped_release release;
    const double* f = F.data();
    const double* q = has_Q ? Q.data() : nullptr;
    const fem::LawRequest request{tangent != "none", false};
    for (py::ssize_t k = 0; k < n; ++k) {
      fem::LawInput in;
      in.F << f[4 * k], f[4 * k + 1], f[4 * k + 2], f[4 * k + 3];
      if (q) {
        const double* qk = q + (Q.shape(0) == 1 ? 0 : 4 * k);
        in.Q << qk[0], qk[1], qk[2], qk[3];
      }
      fem::LawOutput out;
      self.law->evaluate(in, request, out);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) P[std::size_t(4 * k + 2 * i + j)] = out.P(i, j);
      if (!A.empty())  // A(2i+j, 2k+l) = ∂P_ij/∂F_kl: row-major (4, 4) is [i, j, k, l]
        for (int r = 0; r < 4; ++r)
          for (int c = 0; c < 4; ++c) A[std::size_t(16 * k + 4 * r + c)] = out.A(r, c);
      lambda3[std::size_t(k)] = out.lambda3;
    }
  }
  py::object tangent_array = py::none();
  if (tangent == "tensor") tangent_array = adopt(std::move(A), {n, 2, 2, 2, 2});
  else if (tangent == "matrix") tangent_array = adopt(std::move(A), {n, 4, 4});
  return py::make_tuple(adopt(std::move(P), {n, 2, 2}), tangent_array, adopt(std::move(lambda3), {n}));
}

}  // namespace

void bind_law(py::module_& m) {
  using namespace py::literals;
  py::class_<PyLaw>(m, "Law",
                    "A material law from a spec's [law] table (dict or case/project file), evaluated at given F.")
      .def(py::init(&make_law), "spec"_a, py::kw_only(), "base"_a = py::none())
      .def_property_readonly("name", [](const PyLaw& l) { return l.law->name(); })
      .def_property(
          "coefficients",
          [](const PyLaw& l) {
            py::dict d;
            const std::vector<std::string> names = l.law->coefficient_names();
            const Eigen::VectorXd c = l.law->coefficients();
            for (std::size_t k = 0; k < names.size(); ++k) d[py::str(names[k])] = c(Eigen::Index(k));
            return d;
          },
          [](PyLaw& l, const py::dict& values) {
            const std::vector<std::string> names = l.law->coefficient_names();
            Eigen::VectorXd c = l.law->coefficients();
            for (auto item : values) {
              const std::string name = py::str(item.first);
              const auto it = std::find(names.begin(), names.end(), name);
              if (it == names.end())
                throw InputError({"coefficients", 0, name}, "no such coefficient of " + l.law->name(), name, "");
              c(it - names.begin()) = item.second.cast<double>();
            }
            l.law->set_coefficients(c);
          },
          "coefficient → value (set a dict of some of them to change them, e.g. to an Identification's)")
      .def("evaluate", &evaluate, "F"_a, "Q"_a = py::none(), "tangent"_a = "tensor",
           R"(P, A, lambda3 at the deformation gradients F ((2, 2) or (n, 2, 2)).

P: first Piola–Kirchhoff membrane force (n, 2, 2), N/mm. A = ∂P/∂F: (n, 2, 2, 2, 2) with A[n, i, j, k, l] =
∂P_ij/∂F_kl (tangent="tensor"), or (n, 4, 4) rows 2i+j, columns 2k+l ("matrix"), or None ("none").
lambda3 (n,): the out-of-plane stretch. Q: the material axes (columns: course, wale), (2, 2) or (n, 2, 2).)");
}

}  // namespace tricot::python
