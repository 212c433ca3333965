// The JSON readers: an experiment's truth.json (project::read_truth) and identify's checkpoint.json
// (project::read_checkpoint); the first byte picks.
#include "fuzz.hpp"
#include "tricot/project/checkpoint.hpp"
#include "tricot/project/experiment_files.hpp"

using namespace tricot;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string_view text = fuzz::view(data + 1, size - 1);
  try {
    if (data[0] % 2 == 0) {
      fuzz::write(fuzz::scratch(project::kTruthFile), text);
      (void)project::read_truth(fuzz::scratch(project::kTruthFile).parent_path());
    } else {
      const auto file = fuzz::write(fuzz::scratch(project::kCheckpointFile), text);
      (void)project::read_checkpoint(file, "0123456789abcdef");
    }
  } catch (const InputError&) {}
  return 0;
}
