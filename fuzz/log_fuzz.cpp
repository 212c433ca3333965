// The acquisition log reader (io/log.hpp: LabVIEW load-cell logs, camera logs): parse_log with a
// format from the first byte (delimiter, decimal comma, header line), then every column as numbers
// and as a time, and a frame's time from a file name.
#include "fuzz.hpp"
#include "tricot/io/log.hpp"

using namespace tricot;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char kDelimiters[] = {0, ',', ';', '\t'};
  io::LogFormat format;
  format.delimiter = kDelimiters[data[0] & 3];
  format.decimal_comma = (data[0] >> 2) & 1;
  format.header_line = (data[0] >> 3) & 3;
  const std::string_view text = fuzz::view(data + 1, size - 1);
  try {
    format.validate();
    const io::LogTable t = io::parse_log(text, "fuzz.txt", format);
    for (const auto& c : t.columns) {
      try {
        (void)t.numbers(c);
        (void)t.times(c);
      } catch (const InputError&) {}
      (void)t.text(c);
    }
    (void)t.has_column("time");
  } catch (const InputError&) {}
  try {
    (void)io::time_from_file_name(std::string(text.substr(0, 64)));
  } catch (const InputError&) {}
  return 0;
}
