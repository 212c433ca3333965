// JSON for the project's files (checkpoint.json, result.json): vectors as arrays of numbers.
// Include it from .cpp files of src/project only.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace tricot::project {

using json = nlohmann::ordered_json;

inline json vec_json(const Eigen::VectorXd& v) { return json(std::vector<double>(v.data(), v.data() + v.size())); }

inline Eigen::VectorXd json_vec(const json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

/// nlohmann's message without its "[json.exception.type_error.302] " prefix, for one-line errors that
/// name the file and key themselves.
inline std::string json_problem(const std::exception& e) {
  std::string what = e.what();
  if (const auto p = what.find("] "); what.rfind("[json.exception", 0) == 0 && p != std::string::npos) what.erase(0, p + 2);
  return what;
}

}  // namespace tricot::project
