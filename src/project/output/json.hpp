// JSON for the project's files (checkpoint.json, result.json): vectors as arrays of numbers.
// Include it from .cpp files of src/project only.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "tricot/core/error.hpp"

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
  if (const auto p = what.find("] "); what.rfind("[json.exception", 0) == 0 && p != std::string::npos)
    what.erase(0, p + 2);
  return what;
}

/// `j[key]` as T, or an InputError naming the file and the key (`path` + key, e.g. "tests.tension.")
/// with the value found: nlohmann's own type_error names neither.
template <class T>
T json_get(const json& j, const std::string& key, const std::string& file, const std::string& path = "") {
  try {
    return j.at(key).get<T>();
  } catch (const json::exception&) {
    throw InputError({file, 0, path + key}, "missing or of the wrong type",
                     j.is_object() && j.contains(key) ? j[key].dump() : "none");
  }
}

/// `j[key]` as a vector of numbers, or an InputError naming the file and the key.
inline Eigen::VectorXd json_get_vec(const json& j, const std::string& key, const std::string& file,
                                    const std::string& path = "") {
  const auto v = json_get<std::vector<double>>(j, key, file, path);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

/// `j[key]` as T when present (else `fallback`), or an InputError naming the file and the key.
template <class T>
T json_get_or(const json& j, const std::string& key, T fallback, const std::string& file,
              const std::string& path = "") {
  if (!j.is_object() || !j.contains(key)) return fallback;
  const json& v = j[key];
  bool ok = false;
  if constexpr (std::is_same_v<T, std::string>) ok = v.is_string();
  else if constexpr (std::is_same_v<T, bool>) ok = v.is_boolean();
  else if constexpr (std::is_floating_point_v<T>) ok = v.is_number();
  else ok = v.is_number_integer() || v.is_number_unsigned();
  if (!ok)
    throw InputError({file, 0, path + key}, "of the wrong type", v.dump(),
                     std::is_same_v<T, std::string> ? "a string"
                     : std::is_same_v<T, bool>      ? "true or false"
                     : std::is_floating_point_v<T>  ? "a number"
                                                    : "an integer");
  return v.get<T>();
}

}  // namespace tricot::project
