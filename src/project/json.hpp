// JSON for the project's files (checkpoint.json, result.json): vectors as arrays of numbers.
// Include it from .cpp files of src/project only.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vector>

namespace tricot::project {

using json = nlohmann::ordered_json;

inline json vec_json(const Eigen::VectorXd& v) { return json(std::vector<double>(v.data(), v.data() + v.size())); }

inline Eigen::VectorXd json_vec(const json& j) {
  const auto v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

}  // namespace tricot::project
