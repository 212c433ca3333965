// The CSV reader (io::read_csv: forces.csv, field.csv, …) on arbitrary bytes, then its column access.
#include "fuzz.hpp"
#include "tricot/io/files.hpp"

using namespace tricot;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = fuzz::write(fuzz::scratch("fuzz.csv"), fuzz::view(data, size));
  try {
    const io::Table t = io::read_csv(file);
    for (const auto& c : t.columns) (void)t.values(c, file.string());
    (void)t.column("step", file.string());
  } catch (const InputError&) {}
  return 0;
}
