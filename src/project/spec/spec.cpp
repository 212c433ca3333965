#include "tricot/project/spec.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tricot::project {

std::string problem_of(const InputError& e) {
  std::string s = e.what();
  const std::string k = e.where().key;
  if (!k.empty() && s.rfind(k + ": ", 0) == 0) s = s.substr(k.size() + 2);
  return s;
}

void Origin::set_by_flag(const std::string& key, const std::string& flag) {
  flags_[key] = Location{"command line", 0, flag};
}

Location Origin::where(std::string_view key) const {
  if (const auto it = flags_.find(key); it != flags_.end()) return it->second;
  if (table_) return table_->where(key);
  return Location{"", 0, path_.empty() ? std::string(key) : path_ + "." + std::string(key)};
}

void Origin::fail(std::string_view key, const std::string& problem, const std::string& got,
                  const std::string& expected) const {
  throw InputError(where(key), problem, got, expected);
}

bool Origin::owns(const InputError& e) const {
  return e.where().file.empty() && !path_.empty() && e.where().key.rfind(path_ + ".", 0) == 0;
}

void Origin::rethrow(const InputError& e) const {
  Location at = where(e.where().key.substr(path_.size() + 1));
  if (at.file != "command line") at.key = e.where().key;  // a file names the engine's dotted key
  throw InputError(at, problem_of(e));
}

namespace {

// As io writes a real and a key's range (src/io/config.cpp), so that both checks read alike.
std::string real_text(double x) {
  std::string s = fmt::format("{}", x);
  if (std::isfinite(x) && s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

void check_key(const Origin& origin, const io::SectionSpec& table, std::string_view key, const io::Value& value) {
  const auto k =
      std::find_if(table.keys.begin(), table.keys.end(), [&](const io::KeySpec& s) { return s.name == key; });
  if (k == table.keys.end())
    throw std::logic_error("check_key: no key " + std::string(key) + " in [" + table.name + "]");
  auto number = [&](double x, const std::string& at) {
    if (!std::isfinite(x)) origin.fail(at, "must be a finite number", real_text(x), io::range_text(*k));
    if (x < k->min || x > k->max) origin.fail(at, "out of range", real_text(x), io::range_text(*k));
  };
  if (const auto* x = std::get_if<double>(&value)) number(*x, std::string(key));
  if (const auto* i = std::get_if<std::int64_t>(&value))
    if (static_cast<double>(*i) < k->min || static_cast<double>(*i) > k->max)
      origin.fail(key, "out of range", std::to_string(*i), io::range_text(*k));
  if (const auto* r = std::get_if<io::Reals>(&value))
    for (std::size_t i = 0; i < r->size(); ++i) number((*r)[i], fmt::format("{}[{}]", key, i));
  if (const auto* w = std::get_if<std::string>(&value))
    if (!k->choices.empty() && std::find(k->choices.begin(), k->choices.end(), *w) == k->choices.end()) {
      const std::string hint = io::closest_name(*w, k->choices);
      origin.fail(key, "not a valid choice" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
                  "\"" + *w + "\"", io::range_text(*k));
    }
}

}  // namespace tricot::project
