#include "tricot/project/spec.hpp"

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

}  // namespace tricot::project
