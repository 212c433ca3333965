// The TOML config layer: io::parse_config against the verbs' schemas (the first byte picks one), then
// the typed specs built from the validated tree, as `tricot identify`, `simulate` and `dic` do.
#include "fuzz.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/identification_spec.hpp"

using namespace tricot;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int which = data[0] % 3;
  const std::string_view text = fuzz::view(data + 1, size - 1);
  try {
    if (which == 0) {
      const io::Node root = io::parse_config(project::identify_schema(), text, "fuzz.toml");
      (void)project::read_identification_spec(root);
    } else if (which == 1) {
      const io::Node root = io::parse_config(project::case_schema(), text, "fuzz.toml");
      const project::CaseSpec spec = project::CaseSpec::from_config(root);
      spec.check_tests();
      (void)spec.law.law();
    } else {
      const io::Node root = io::parse_config(project::dic_schema(), text, "fuzz.toml");
      (void)project::DicSpec::from_config(root, "/nonexistent");
    }
  } catch (const InputError&) {}
  return 0;
}
