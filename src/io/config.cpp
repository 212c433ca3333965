#include "tricot/io/config.hpp"

#include "tricot/core/options.hpp"

#include <utility>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <toml++/toml.h>

#include "tricot/io/files.hpp"

namespace tricot::io {

namespace {

std::string format_real(double x) {
  std::string s = fmt::format("{}", x);
  if (std::isfinite(x) && s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

int line_of(const toml::node& n) { return static_cast<int>(n.source().begin.line); }

std::string join(std::string_view a, std::string_view b) {
  return a.empty() ? std::string(b) : std::string(a) + "." + std::string(b);
}

}  // namespace

std::string range_text(const KeySpec& k) {
  if (!k.choices.empty()) {
    std::string s = "one of ";
    for (std::size_t i = 0; i < k.choices.size(); ++i) s += (i ? ", " : "") + k.choices[i];
    return s;
  }
  return tricot::range_text(k.min, k.max);
}

std::string to_toml(const Value& v) {
  struct {
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double x) const { return format_real(x); }
    std::string operator()(const std::string& s) const {
      std::ostringstream o;
      o << toml::value<std::string>(s);
      return o.str();
    }
    std::string operator()(const Reals& r) const {
      std::string s = "[";
      for (std::size_t i = 0; i < r.size(); ++i) s += (i ? ", " : "") + format_real(r[i]);
      return s + "]";
    }
    std::string operator()(const Strings& r) const {
      std::string s = "[";
      for (std::size_t i = 0; i < r.size(); ++i) s += (i ? ", " : "") + (*this)(r[i]);
      return s + "]";
    }
  } visitor;
  return std::visit(visitor, v);
}

std::string closest_name(std::string_view word, const Strings& names) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;  // accept distance <= max(2, n/3)
  for (const auto& n : names) {
    // Levenshtein distance, two rows.
    std::vector<std::size_t> prev(n.size() + 1), cur(n.size() + 1);
    for (std::size_t j = 0; j <= n.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= n.size(); ++j)
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (word[i - 1] != n[j - 1])});
      std::swap(prev, cur);
    }
    if (prev[n.size()] < best_d) {
      best_d = prev[n.size()];
      best = n;
    }
  }
  return best;
}

// ---------------------------------------------------------------------------------------------------
// Node access

const Node::Entry& Node::entry(std::string_view key) const {
  auto it = entries_.find(key);
  // Asking for a key the schema does not declare is a programming error, not bad input.
  if (it == entries_.end()) throw std::logic_error("config: no key '" + join(path_, key) + "' in schema");
  return it->second;
}

template <class T>
const T& Node::get(std::string_view key) const {
  const Entry& e = entry(key);
  if (!std::holds_alternative<T>(e.value))
    throw std::logic_error("config: key '" + join(path_, key) + "' has another type in the schema");
  return std::get<T>(e.value);
}

double Node::real(std::string_view key) const { return get<double>(key); }
std::int64_t Node::integer(std::string_view key) const { return get<std::int64_t>(key); }
bool Node::boolean(std::string_view key) const { return get<bool>(key); }
const std::string& Node::string(std::string_view key) const { return get<std::string>(key); }
const Reals& Node::reals(std::string_view key) const { return get<Reals>(key); }
const Strings& Node::strings(std::string_view key) const { return get<Strings>(key); }
const Value& Node::value(std::string_view key) const { return entry(key).value; }
bool Node::given(std::string_view key) const { return entry(key).given; }

const Node& Node::section(std::string_view name) const {
  auto it = sections_.find(name);
  if (it == sections_.end()) throw std::logic_error("config: no section '" + join(path_, name) + "'");
  return it->second;
}

Node& Node::section(std::string_view name) { return const_cast<Node&>(std::as_const(*this).section(name)); }

const std::vector<Node>& Node::array(std::string_view name) const {
  auto it = arrays_.find(name);
  if (it == arrays_.end()) throw std::logic_error("config: no array '" + join(path_, name) + "'");
  return it->second;
}

void Node::set(std::string_view key, Value v) {
  auto it = entries_.find(key);
  if (it == entries_.end() || it->second.value.index() != v.index())
    throw std::logic_error("config: cannot override '" + join(path_, key) + "' with that type");
  it->second.value = std::move(v);
  it->second.given = true;
  it->second.line = 0;
}

Location Node::where(std::string_view key) const {
  auto it = entries_.find(key);
  int line = (it != entries_.end() && it->second.line > 0) ? it->second.line : line_;
  return {file_, line, join(path_, key)};
}

void Node::fail(std::string_view key, const std::string& problem, const std::string& got,
                const std::string& expected) const {
  throw InputError(where(key), problem, got, expected);
}

// ---------------------------------------------------------------------------------------------------
// Building a Node from TOML

class NodeBuilder {
 public:
  NodeBuilder(std::string file) : file_(std::move(file)) {}

  Node build(const SectionSpec& spec, const toml::table* t, const std::string& path, int line) {
    Node n;
    n.file_ = file_;
    n.path_ = path;
    n.line_ = line;
    Strings known;
    for (const auto& k : spec.keys) {
      known.push_back(k.name);
      Node::Entry e{k.default_value, &k, line, false};
      if (t) {
        if (const toml::node* v = t->get(k.name)) {
          e.value = convert(k, *v, join(path, k.name));
          e.line = line_of(*v);
          e.given = true;
        }
      }
      n.entries_.emplace(k.name, std::move(e));
    }
    for (const auto& s : spec.sections) {
      known.push_back(s.name);
      const toml::node* sub = t ? t->get(s.name) : nullptr;
      const std::string sub_path = join(path, s.name);
      if (s.array) {
        std::vector<Node> items;
        if (sub) {
          const toml::array* arr = sub->as_array();
          if (!arr) fail(*sub, sub_path, "must be an array of tables, written [[" + sub_path + "]]");
          for (std::size_t i = 0; i < arr->size(); ++i) {
            const toml::node& item = (*arr)[i];
            if (!item.is_table()) fail(item, sub_path, "each entry must be a table");
            items.push_back(build(s, item.as_table(), fmt::format("{}[{}]", sub_path, i), line_of(item)));
          }
        }
        n.arrays_.emplace(s.name, std::move(items));
      } else {
        const toml::table* st = nullptr;
        if (sub) {
          st = sub->as_table();
          if (!st) fail(*sub, sub_path, "must be a table, written [" + sub_path + "]");
        }
        n.sections_.emplace(s.name, build(s, st, sub_path, sub ? line_of(*sub) : line));
      }
    }
    if (t) {
      for (const auto& [k, v] : *t) {
        if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
        std::string hint = closest_name(k.str(), known);
        fail(v, join(path, k.str()), "unknown key" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"));
      }
    }
    return n;
  }

 private:
  [[noreturn]] void fail(const toml::node& at, const std::string& key, const std::string& problem,
                         const std::string& got = {}, const std::string& expected = {}) const {
    throw InputError({file_, line_of(at), key}, problem, got, expected);
  }

  double number(const KeySpec& k, const toml::node& v, const std::string& key) const {
    double x;
    if (auto i = v.value_exact<std::int64_t>()) x = static_cast<double>(*i);
    else if (auto d = v.value_exact<double>()) x = *d;
    else fail(v, key, "must be a number", describe(v), range_text(k));
    if (!std::isfinite(x)) fail(v, key, "must be a finite number", format_real(x), range_text(k));
    if (x < k.min || x > k.max) fail(v, key, "out of range", format_real(x), range_text(k));
    return x;
  }

  static std::string describe(const toml::node& v) {
    if (auto str = v.value_exact<std::string>()) return "\"" + *str + "\"";
    std::ostringstream o;
    v.visit([&](auto&& x) { o << x; });
    std::string s = o.str();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
  }

  Value convert(const KeySpec& k, const toml::node& v, const std::string& key) const {
    switch (k.default_value.index()) {
      case 0:
        if (auto b = v.value_exact<bool>()) return *b;
        fail(v, key, "must be true or false", describe(v));
      case 1: {
        auto i = v.value_exact<std::int64_t>();
        if (!i) fail(v, key, "must be an integer", describe(v), range_text(k));
        if (*i < k.min || *i > k.max) fail(v, key, "out of range", std::to_string(*i), range_text(k));
        return *i;
      }
      case 2: return number(k, v, key);
      case 3: {
        auto s = v.value_exact<std::string>();
        if (!s && k.or_number && (v.is_integer() || v.is_floating_point())) return number(k, v, key);
        if (!s) fail(v, key, "must be a string", describe(v), range_text(k));
        if (!k.choices.empty() && std::find(k.choices.begin(), k.choices.end(), *s) == k.choices.end()) {
          std::string hint = closest_name(*s, k.choices);
          fail(v, key, "not a valid choice" + (hint.empty() ? std::string() : "; did you mean '" + hint + "'?"),
               "\"" + *s + "\"", range_text(k));
        }
        return *s;
      }
      case 4: {
        const toml::array* a = v.as_array();
        if (!a) fail(v, key, "must be a list of numbers", describe(v));
        Reals r;
        for (std::size_t i = 0; i < a->size(); ++i) {
          r.push_back(number(k, (*a)[i], fmt::format("{}[{}]", key, i)));
          if (k.increasing && i > 0 && r[i] <= r[i - 1])
            fail((*a)[i], fmt::format("{}[{}]", key, i), "must be larger than the value before it", format_real(r[i]),
                 "> " + format_real(r[i - 1]));
        }
        return r;
      }
      default: {
        const toml::array* a = v.as_array();
        if (!a) fail(v, key, "must be a list of strings", describe(v));
        Strings r;
        for (std::size_t i = 0; i < a->size(); ++i) {
          auto s = (*a)[i].value_exact<std::string>();
          if (!s) fail((*a)[i], fmt::format("{}[{}]", key, i), "must be a string", describe((*a)[i]));
          r.push_back(*s);
        }
        return r;
      }
    }
  }

  std::string file_;
};

Node parse_config(const SectionSpec& schema, std::string_view text, const std::string& name) {
  toml::table t;
  try {
    t = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError({name, static_cast<int>(e.source().begin.line), ""},
                     "TOML syntax error: " + std::string(e.description()));
  }
  return NodeBuilder(name).build(schema, &t, "", 1);
}

Node read_config(const SectionSpec& schema, const std::string& file) {
  return parse_config(schema, read_text(file), file);
}

Node default_config(const SectionSpec& schema) { return NodeBuilder("<defaults>").build(schema, nullptr, "", 0); }

namespace {

void print_comment(std::string& out, const std::string& text) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out += line.empty() ? "#\n" : "# " + line + "\n";
}

// An array of tables inside another table (e.g. [[test.boundary]]) is optional: its example entry is
// printed commented out, so that the printed config runs as it is.
void print_section(std::string& out, const SectionSpec& s, const std::string& path, bool commented = false) {
  commented = commented || (s.array && path.find('.') != std::string::npos);
  const std::string lead = commented ? "# " : "";
  if (!path.empty()) {
    out += "\n";
    print_comment(out, s.help);
    if (s.array)
      print_comment(
          out, commented ? "(optional: uncomment, and repeat once per entry)" : "(repeat this table once per entry)");
    out += lead + (s.array ? "[[" + path + "]]\n" : "[" + path + "]\n");
  } else if (!s.help.empty()) {
    print_comment(out, s.help);
    out += "\n";
  }
  for (const auto& k : s.keys) {
    std::string help = k.help;
    const std::string r = range_text(k);
    if (!r.empty()) help += (help.empty() ? "" : " ") + std::string("[") + r + "]";
    print_comment(out, help);
    out += (k.alternative ? "# " : lead) + k.name + " = " + to_toml(k.default_value) + "\n";
  }
  for (const auto& sub : s.sections) print_section(out, sub, join(path, sub.name), commented);
}

}  // namespace

std::string print_config(const SectionSpec& schema) {
  std::string out;
  print_section(out, schema, "");
  return out;
}

}  // namespace tricot::io
