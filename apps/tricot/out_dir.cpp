#include <filesystem>

#include "verbs.hpp"

namespace tricot::cli {

namespace fs = std::filesystem;

void check_out_dir(const std::string& dir) {
  if (dir.empty())
    throw InputError({"command line", 0, "-o"}, "empty output folder", "''", "a folder path (use . for this folder)");
  // The folder, or its nearest existing ancestor, must be a folder: checked before any work is done.
  std::error_code ec;
  for (fs::path p = dir; !p.empty(); p = p.parent_path()) {
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st)) {
      if (!fs::is_directory(st))
        throw FileError({p.string(), 0, ""}, p == fs::path(dir) ? "the output folder is a file" : "not a folder", "",
                        "a folder, or a path that does not exist yet");
      break;
    }
    if (p == p.parent_path()) break;
  }
}

}  // namespace tricot::cli
