#include <iostream>

#include "verbs.hpp"

namespace tricot::cli {

void add_print_config(CLI::App* verb, std::function<io::SectionSpec()> schema) {
  verb->add_flag_callback(
      "--print-config",
      [schema] {
        std::cout << io::print_config(schema());
        throw CLI::Success();
      },
      "Print the fully commented default config and exit");
}

}  // namespace tricot::cli
