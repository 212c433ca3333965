// The built-in examples (see examples.hpp); example_files() is generated (cmake/TricotEmbed.cmake).
#include "tricot/project/examples.hpp"

#include <stdexcept>

namespace tricot::project {

namespace {

constexpr std::string_view kBlank = " \t";

std::string_view trim(std::string_view s) {
  const std::size_t a = s.find_first_not_of(kBlank);
  if (a == std::string_view::npos) return {};
  return s.substr(a, s.find_last_not_of(kBlank) - a + 1);
}

// Where the comment of a TOML line starts (a '#' outside any string), or the line's end.
std::size_t comment_start(std::string_view line, std::size_t from) {
  char quote = 0;
  for (std::size_t i = from; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == '\\' && quote == '"') ++i;
      else if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#') {
      return i;
    }
  }
  return line.size();
}

// A value as TOML text; a string as a basic string, "…", as the examples write them (io::to_toml
// writes toml++'s literal strings, '…').
std::string toml_text(const io::Value& v) {
  const auto* s = std::get_if<std::string>(&v);
  if (!s) return io::to_toml(v);
  std::string q = "\"";
  for (const char c : *s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c == '\n' ? std::string("\\n") : std::string(1, c);
  }
  return q + "\"";
}

}  // namespace

std::string_view example_file(std::string_view path) {
  for (const ExampleFile& f : example_files())
    if (f.path == path) return f.text;
  throw std::logic_error("examples/" + std::string(path) + " is not built into tricot (src/project/CMakeLists.txt)");
}

std::string with_value(std::string_view toml, std::string_view table, std::string_view key, const io::Value& value) {
  std::string_view current;  // the table of the line
  for (std::size_t at = 0; at < toml.size();) {
    const std::size_t end = std::min(toml.find('\n', at), toml.size());
    const std::string_view line = toml.substr(at, end - at);
    const std::size_t first = line.find_first_not_of(kBlank);
    if (first != std::string_view::npos && line[first] == '[') {
      const std::size_t open = line.find_first_not_of('[', first);
      current = trim(line.substr(open, line.find(']', open) - open));
    } else if (current == table && first != std::string_view::npos && line.substr(first).starts_with(key)) {
      const std::size_t eq = line.find_first_not_of(kBlank, first + key.size());
      const std::size_t v0 = eq == std::string_view::npos ? eq : line.find_first_not_of(kBlank, eq + 1);
      if (v0 != std::string_view::npos && line[eq] == '=') {
        std::size_t v1 = comment_start(line, v0);
        while (v1 > v0 && kBlank.find(line[v1 - 1]) != std::string_view::npos) --v1;
        return std::string(toml.substr(0, at + v0)) + toml_text(value) + std::string(toml.substr(at + v1));
      }
    }
    at = end + 1;
  }
  throw std::logic_error("with_value: no key '" + std::string(key) + "' in [" + std::string(table) + "]");
}

}  // namespace tricot::project
