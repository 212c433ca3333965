// OutputDir: staging, publication with renames, the per-verb manifest and the publication journal.
#include "tricot/project/output_dir.hpp"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cerrno>
#include <cstring>
#include <set>
#include <system_error>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "output/json.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

fs::path manifest_of(const fs::path& dir, const std::string& verb) { return dir / (".tricot-" + verb + ".json"); }
fs::path journal_of(const fs::path& dir, const std::string& verb) {
  return dir / (".tricot-" + verb + ".publishing.json");
}

std::vector<std::string> read_list(const fs::path& file, const char* key) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return {};
  try {
    auto list = json::parse(io::read_text(file)).at(key).get<std::vector<std::string>>();
    // Only paths inside the folder: a record never names a file elsewhere.
    std::erase_if(list, [](const std::string& f) {
      const fs::path p(f);
      return f.empty() || p.is_absolute() ||
             std::any_of(p.begin(), p.end(), [](const fs::path& c) { return c == ".."; });
    });
    return list;
  } catch (const json::exception& e) {
    throw InputError({file.string(), 0, key}, "not a tricot output record: " + json_problem(e));
  }
}

// Removes `file` and then its parent folders up to `dir` while they are empty.
void remove_with_empty_parents(const fs::path& dir, const fs::path& file) {
  std::error_code ec;
  fs::remove(file, ec);
  for (fs::path p = file.parent_path(); p.string().size() > dir.string().size(); p = p.parent_path())
    if (!fs::remove(p, ec)) break;  // not empty (or gone): stop
}

// Carries out DIR's journal of `verb`: removes the earlier run's files, moves the staged ones (those
// a killed publication already moved are skipped), writes the manifest and removes the staging
// folder and the journal. Every step can be repeated, so a publication killed anywhere completes.
void roll_forward(const fs::path& dir, const std::string& verb) {
  const fs::path journal = journal_of(dir, verb);
  const auto remove = read_list(journal, "remove");
  const auto move = read_list(journal, "move");
  auto files = move;
  for (const auto& f : read_list(journal, "keep")) files.push_back(f);
  std::sort(files.begin(), files.end());
  const fs::path staging = OutputDir::staging_of(dir, verb);
  for (const auto& f : remove) remove_with_empty_parents(dir, dir / f);
  for (const auto& f : move) {
    const fs::path from = staging / f, to = dir / f;
    std::error_code ec;
    if (!fs::exists(from, ec)) continue;
    fs::create_directories(to.parent_path(), ec);
    fs::rename(from, to, ec);
    if (ec) throw FileError({to.string(), 0, ""}, "cannot publish the file: " + ec.message());
  }
  json m;
  m["verb"] = verb;
  m["files"] = files;
  io::write_atomic(manifest_of(dir, verb), m.dump(1) + "\n");
  std::error_code ec;
  fs::remove_all(staging, ec);
  fs::remove(journal, ec);
}

}  // namespace

fs::path OutputDir::staging_of(const fs::path& dir, const std::string& verb) { return dir / (".tricot-" + verb); }

std::vector<std::string> OutputDir::published(const fs::path& dir, const std::string& verb) {
  return read_list(manifest_of(dir, verb), "files");
}

OutputDir::OutputDir(fs::path dir, std::string verb, bool keep_staging)
    : dir_(std::move(dir)), staging_(staging_of(dir_, verb)), verb_(std::move(verb)) {
  std::error_code ec;
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec))
    throw FileError({dir_.string(), 0, ""}, "the output folder is a file", "", "a folder (or a path to create)");
  fs::create_directories(dir_, ec);
  if (ec) throw FileError({dir_.string(), 0, ""}, "cannot create the output folder: " + ec.message());
  const fs::path lock = dir_ / (".tricot-" + verb_ + ".lock");
  lock_ = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (lock_ < 0)
    throw FileError({lock.string(), 0, ""}, std::string("cannot create the folder's lock: ") + std::strerror(errno));
  if (::flock(lock_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_);
    throw FileError({dir_.string(), 0, ""}, "another tricot " + verb_ + " is writing this folder now", "",
                    "wait for it to end, or another output folder");
  }
  if (fs::exists(journal_of(dir_, verb_), ec)) roll_forward(dir_, verb_);  // a killed publication
  if (!keep_staging) fs::remove_all(staging_, ec);
}

OutputDir::~OutputDir() {
  if (lock_ >= 0) ::close(lock_);  // releases the flock
}

void OutputDir::publish(const std::vector<std::string>& scope) {
  // Testing aid: a run killed with everything staged (tests/cli/outputs_test.cpp).
  if (const char* v = std::getenv("TRICOT_TEST_KILL_BEFORE_PUBLISH"); v && verb_ == v) std::raise(SIGKILL);
  std::vector<std::string> written;
  std::error_code ec;
  if (fs::is_directory(staging_, ec))
    for (const auto& e : fs::recursive_directory_iterator(staging_))
      if (e.is_regular_file()) written.push_back(e.path().lexically_relative(staging_).generic_string());
  std::sort(written.begin(), written.end());
  const std::set<std::string> now(written.begin(), written.end());
  const auto in_scope = [&](const std::string& f) {
    return scope.empty() ||
           std::any_of(scope.begin(), scope.end(), [&](const std::string& p) { return f.starts_with(p); });
  };
  std::vector<std::string> stale, kept;
  for (const auto& f : published(dir_, verb_)) {
    if (now.count(f)) continue;
    (in_scope(f) ? stale : kept).push_back(f);
  }
  json j;
  j["verb"] = verb_;
  j["remove"] = stale;
  j["move"] = written;
  j["keep"] = kept;  // a partial run's: the earlier files it leaves, still the folder's
  io::write_atomic(journal_of(dir_, verb_), j.dump(1) + "\n");
  roll_forward(dir_, verb_);
}

}  // namespace tricot::project
