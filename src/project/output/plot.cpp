#include "output/plot.hpp"

#include <fmt/format.h>

#include "tricot/io/files.hpp"

namespace tricot::project {

void plot(const Figure& figure, const std::string& body, const Log& log) {
  const std::string header = fmt::format(
      "set terminal pngcairo size {},{} font \",{}\"{}\nset output {}\nset datafile separator \",\"\n", figure.width,
      figure.height, figure.font_size, figure.enhanced ? "" : " noenhanced", io::gnuplot_quote(figure.png));
  std::string why;
  if (!io::run_gnuplot(header + body, &why)) log.print("  (no " + figure.name + ": " + why + ")");
}

}  // namespace tricot::project
