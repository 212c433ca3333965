#include "tricot/core/error.hpp"

#include <gtest/gtest.h>

using namespace tricot;

TEST(InputError, MessageNamesFileLineKeyValueAndRange) {
  InputError e({"case.toml", 12, "mesh.width"}, "out of range", "-3.0", ">= 0");
  EXPECT_STREQ(e.what(), "case.toml:12: mesh.width: out of range (got -3.0, expected >= 0)");
  EXPECT_EQ(e.exit_code(), ExitCode::usage);
}

TEST(InputError, LeavesOutWhatIsUnknown) {
  EXPECT_EQ(format_error({}, "bad", "", ""), "bad");
  EXPECT_EQ(format_error({"f.csv", 0, ""}, "bad", "", "x"), "f.csv: bad (expected x)");
}

TEST(FileError, MapsToExitCodeThree) {
  FileError e({"missing.png", 0, ""}, "cannot open the file");
  EXPECT_EQ(e.exit_code(), ExitCode::input_missing);
  EXPECT_STREQ(e.what(), "missing.png: cannot open the file");
}
