// Transactional outputs through a verb (issue 14, src/project/output/output_dir.cpp): a rerun into a folder
// that holds a different earlier run, killed before it publishes (TRICOT_TEST_KILL_BEFORE_PUBLISH), must
// leave the earlier run whole; completed, it must leave only its own files.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cli.hpp"
#include "tricot/io/files.hpp"

namespace tricot::test {

/// Every file of a folder but the hidden records and staging (.tricot-*), with its content.
inline std::map<std::string, std::string> snapshot(const std::filesystem::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    const std::string rel = e.path().lexically_relative(dir).generic_string();
    if (e.is_regular_file() && rel.rfind(".tricot-", 0) != 0) out[rel] = io::read_text(e.path());
  }
  return out;
}

inline std::vector<std::string> names(const std::map<std::string, std::string>& m) {
  std::vector<std::string> v;
  for (const auto& [k, _] : m) v.push_back(k);
  return v;
}

/// Runs `earlier` into ROOT/out, then `rerun` killed before publishing, then `rerun` whole; `rerun`
/// also runs into a fresh ROOT/alone, for the file list a clean run leaves. `verb` names the kill switch.
inline void expect_no_mix(const std::string& verb, const std::filesystem::path& root,
                          const std::function<std::string(const std::filesystem::path&)>& earlier,
                          const std::function<std::string(const std::filesystem::path&)>& rerun) {
  const std::filesystem::path out = root / "out", alone = root / "alone";
  ASSERT_EQ(run_tricot(earlier(out)).exit_code, 0);
  const auto before = snapshot(out);
  ASSERT_FALSE(before.empty());

  ::setenv("TRICOT_TEST_KILL_BEFORE_PUBLISH", verb.c_str(), 1);
  const auto killed = run_tricot(rerun(out));
  ::unsetenv("TRICOT_TEST_KILL_BEFORE_PUBLISH");
  ASSERT_NE(killed.exit_code, 0);
  EXPECT_EQ(snapshot(out), before) << "the killed rerun left files beside the earlier run";
  EXPECT_TRUE(std::filesystem::exists(out / (".tricot-" + verb)));  // its files, apart

  ASSERT_EQ(run_tricot(rerun(out)).exit_code, 0);
  ASSERT_EQ(run_tricot(rerun(alone)).exit_code, 0);
  const auto after = snapshot(out);
  EXPECT_EQ(names(after), names(snapshot(alone))) << "files of the earlier run are left";
  EXPECT_NE(after, before);
  EXPECT_FALSE(std::filesystem::exists(out / (".tricot-" + verb)));
}

}  // namespace tricot::test
