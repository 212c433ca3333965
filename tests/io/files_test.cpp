#include "tricot/io/files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "tricot/core/error.hpp"
#include "testing/paths.hpp"

using namespace tricot;
using namespace tricot::io;

TEST(Csv, RoundTripsDoublesExactly) {
  const auto dir = test::scratch_dir("csv_roundtrip");
  Table t{{"step", "force"}, {{1, 0.1}, {2, 1.0 / 3.0}}, {}};
  write_atomic(dir / "a.csv", to_csv(t));
  Table r = read_csv(dir / "a.csv");
  EXPECT_EQ(r.columns, t.columns);
  EXPECT_EQ(r.rows, t.rows);
  EXPECT_EQ(r.values("force", "a.csv")[1], 1.0 / 3.0);
}

TEST(Csv, TableNumbersHave17SignificantDigits) {
  const Table t{{"step", "force"}, {{1, 0.1}, {2, -2.5e-7}}, {}};
  EXPECT_EQ(to_csv(t), "step,force\n1,0.10000000000000001\n2,-2.4999999999999999e-07\n");
}

TEST(Csv, WriterQuotesTextCellsOnlyWhereRfc4180NeedsIt) {
  CsvWriter csv;
  csv.row({"image", "status", "x"});
  csv.text("frame_0001.png").text("ok").number(0.1).end_row();
  csv.text("a,b.png").text("say \"hi\"").number_or_empty(NAN, CsvFormat::decimals(5)).end_row();
  csv.text("two\nlines").text("cr\r").number(1.0 / 3.0, CsvFormat::decimals(5)).end_row();
  csv.integer(-7).text("").number(2.5, CsvFormat::significant(9)).number(0.3, CsvFormat::shortest()).end_row();
  csv.end_row();
  EXPECT_EQ(csv.take(),
            "image,status,x\n"
            "frame_0001.png,ok,0.10000000000000001\n"
            "\"a,b.png\",\"say \"\"hi\"\"\",\n"
            "\"two\nlines\",\"cr\r\",0.33333\n"
            "-7,,2.5,0.3\n"
            "\n");
  EXPECT_EQ(csv.take(), "");  // take() leaves the writer empty, for the next frame's rows
}

TEST(Csv, NanCellNamesFileLineAndColumn) {
  const auto dir = test::scratch_dir("csv_nan");
  std::ofstream(dir / "b.csv") << "step,force\n1,0.5\n2,nan\n";
  try {
    read_csv(dir / "b.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "b.csv").string() + ":3: force: not a finite number (got \"nan\", expected a finite number)");
  }
}

TEST(Csv, RaggedRowIsAnError) {
  const auto dir = test::scratch_dir("csv_ragged");
  std::ofstream(dir / "c.csv") << "a,b\n1,2\n3\n";
  EXPECT_THROW(read_csv(dir / "c.csv"), InputError);
}

TEST(Csv, MissingFileIsAFileError) { EXPECT_THROW(read_csv("/nonexistent.csv"), FileError); }

TEST(WriteAtomic, LeavesNoTemporaryBehind) {
  const auto dir = test::scratch_dir("atomic");
  write_atomic(dir / "sub" / "x.txt", "hello");
  EXPECT_EQ(read_text(dir / "sub" / "x.txt"), "hello");
  int n = 0;
  for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(dir / "sub")) ++n;
  EXPECT_EQ(n, 1);
}

TEST(Csv, AByteOrderMarkAndCrlfLineEndsAreRead) {
  const auto dir = test::scratch_dir("csv_bom");
  std::ofstream(dir / "b.csv", std::ios::binary) << "\xEF\xBB\xBFstep,force\r\n1,2.5\r\n";
  const Table t = read_csv(dir / "b.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"step", "force"}));
  EXPECT_EQ(t.rows.at(0).at(1), 2.5);
}

TEST(ReadText, AFolderIsAFileErrorNamingIt) {
  const auto dir = test::scratch_dir("read_folder");
  try {
    read_text(dir);
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": is a folder, not a file (expected a regular file)");
  }
}

TEST(Gnuplot, AFailingScriptReturnsGnuplotsMessageAndPrintsNothing) {
  std::string why;
  testing::internal::CaptureStdout();
  const bool ok = run_gnuplot("this_is_not_a_command\n", &why);
  const std::string printed = testing::internal::GetCapturedStdout();
  EXPECT_FALSE(ok);
  EXPECT_TRUE(printed.empty()) << printed;
  if (why.find("not installed") != std::string::npos) GTEST_SKIP() << why;
  EXPECT_NE(why.find("gnuplot failed: "), std::string::npos) << why;
  EXPECT_EQ(why.find("is gnuplot-nox installed"), std::string::npos) << why;
}
