// The outside contract of `tricot` (docs/design.md): help, version, exit codes for usage errors.
#include <gtest/gtest.h>

#include "testing/cli.hpp"

using tricot::test::run_tricot;

TEST(Cli, HelpListsEveryVerbAndExitsZero) {
  const auto r = run_tricot("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* verb : {"simulate", "identify", "dic", "synth", "demo"})
    EXPECT_NE(r.out.find(verb), std::string::npos) << verb;
}

TEST(Cli, EveryVerbHasHelp) {
  for (const char* verb : {"simulate", "identify", "dic", "synth", "demo"}) {
    const auto r = run_tricot(std::string(verb) + " --help");
    EXPECT_EQ(r.exit_code, 0) << verb << ": " << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << verb;
  }
}

TEST(Cli, UnknownVerbIsAUsageError) {
  const auto r = run_tricot("frobnicate");
  EXPECT_EQ(r.exit_code, 2);
}

TEST(Cli, NoVerbIsAUsageError) { EXPECT_EQ(run_tricot("").exit_code, 2); }

TEST(Cli, VersionPrintsTheVersion) {
  const auto r = run_tricot("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("tricot 0.1.0"), std::string::npos);
}
