#include "tricot/io/log.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <fstream>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::io;

namespace {

// The message of the InputError that `f` throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// What a French LabVIEW VI writes: 10 metadata lines, a tab header with units, decimal commas, CRLF, BOM.
const char* labview =
    "\xEF\xBB\xBFLabVIEW Measurement\r\n"
    "Writer_Version\t2\r\n"
    "Reader_Version\t2\r\n"
    "Separator\tTab\r\n"
    "Decimal_Separator\t,\r\n"
    "Date\t2026/11/23\r\n"
    "Time\t14:02:11,5\r\n"
    "Operator\tJ. Martin\r\n"
    "Sample rate (Hz)\t100\r\n"
    "***End_of_Header***\r\n"
    "Temps (s)\tForce [N]\tTraverse [mm]\t\r\n"
    "0\t0,512\t0\t\r\n"
    "0,01\t0,498\t0,001\t\r\n"
    "0,02\t1,25e-1\t0,002\t\r\n";

}  // namespace

TEST(Log, ReadsALabviewTabFileWithDecimalCommaAndATenLineHeader) {
  const LogTable t = parse_log(labview, "run1.lvm");
  EXPECT_EQ(t.format.delimiter, '\t');
  EXPECT_TRUE(t.format.decimal_comma);
  EXPECT_EQ(t.metadata.size(), 10u);
  EXPECT_EQ(t.columns, (std::vector<std::string>{"Temps (s)", "Force [N]", "Traverse [mm]"}));
  EXPECT_EQ(t.units, (std::vector<std::string>{"s", "N", "mm"}));
  EXPECT_EQ(t.lines, (std::vector<int>{12, 13, 14}));
  EXPECT_EQ(t.times("temps"), (std::vector<double>{0, 0.01, 0.02}));
  EXPECT_EQ(t.numbers("FORCE"), (std::vector<double>{0.512, 0.498, 0.125}));
  EXPECT_EQ(t.numbers("traverse [mm]")[2], 0.002);
}

TEST(Log, ReadsACsvWithUnitsInTheHeaderAndMetadataAbove) {
  const LogTable t = parse_log(
      "# Instron export\nSpecimen,K12\nTime (s),Extension (mm),Load (N)\n0.0,0.00,0.10\n0.5,0.25,2.5\n1.0,0.50,4.75\n",
      "instron.csv");
  EXPECT_EQ(t.format.delimiter, ',');
  EXPECT_FALSE(t.format.decimal_comma);
  EXPECT_EQ(t.metadata.size(), 2u);
  EXPECT_EQ(t.numbers("load"), (std::vector<double>{0.1, 2.5, 4.75}));
  EXPECT_EQ(t.numbers("Extension"), (std::vector<double>{0, 0.25, 0.5}));
}

TEST(Log, ReadsASemicolonCsvWithDecimalComma) {
  const LogTable t = parse_log("Zeit [s];Kraft [N]\n0,0;1,5\n0,1;2,5\n", "de.csv");
  EXPECT_EQ(t.format.delimiter, ';');
  EXPECT_TRUE(t.format.decimal_comma);
  EXPECT_EQ(t.numbers("kraft"), (std::vector<double>{1.5, 2.5}));
}

TEST(Log, UnknownColumnGetsADidYouMeanAndTheListOfColumns) {
  const LogTable t = parse_log(labview, "run1.lvm");
  EXPECT_EQ(error_of([&] { t.numbers("forse"); }),
            "run1.lvm: forse: no such column in the log; did you mean 'Force [N]'? "
            "(expected one of 'Temps (s)', 'Force [N]', 'Traverse [mm]')");
  EXPECT_EQ(error_of([&] { t.numbers("strain"); }),
            "run1.lvm: strain: no such column in the log (expected one of 'Temps (s)', 'Force [N]', 'Traverse [mm]')");
}

TEST(Log, TextOrNanCellNamesFileLineAndColumn) {
  const LogTable t = parse_log("time,force\n0,1\n0.1,abc\n0.2,nan\n", "log.csv");
  EXPECT_EQ(error_of([&] { t.numbers("force"); }),
            "log.csv:3: force: not a finite number (got \"abc\", expected a finite number)");
  const LogTable u = parse_log("time,force\n0,1\n0.1,2\n0.2,NaN\n", "log.csv");
  EXPECT_EQ(error_of([&] { u.numbers("force"); }),
            "log.csv:4: force: not a finite number (got \"NaN\", expected a finite number)");
  EXPECT_NO_THROW(u.numbers("time"));
}

TEST(Log, AnEmptyCellIsAMissingValueWhereAskedAndTextStillAnError) {
  // A DIC tool's tracks: the point lost in the second frame has empty cells; decimal comma as written.
  const LogTable t = parse_log("frame;x [mm];y [mm]\n0;1,5;2,25\n1;;\n2;1,75;2,5\n", "tracks.csv");
  const auto x = t.numbers_or_empty("x");
  ASSERT_EQ(x.size(), 3u);
  EXPECT_EQ(x[0], 1.5);
  EXPECT_TRUE(std::isnan(x[1]));
  EXPECT_EQ(x[2], 1.75);
  EXPECT_EQ(error_of([&] { t.numbers("x"); }), "tracks.csv:3: x [mm]: empty cell (got \"\", expected a finite number)");
  const LogTable u = parse_log("frame,x\n0,1\n1,lost\n", "tracks.csv");
  EXPECT_EQ(error_of([&] { u.numbers_or_empty("x"); }),
            "tracks.csv:3: x: not a finite number (got \"lost\", expected a finite number, or an empty cell for a "
            "missing value)");
}

TEST(Log, TimeGoingBackwardsNamesTheLine) {
  const LogTable t = parse_log("t [s]\tF [N]\n0,0\t1\n0,1\t1\n0,05\t1\n", "back.txt");
  EXPECT_EQ(error_of([&] { t.times("t"); }),
            "back.txt:4: t [s]: time goes backwards (got 0.05, expected > 0.1 (line 3))");
}

TEST(Log, RowWithTooManyCellsIsAnError) {
  EXPECT_EQ(error_of([] { parse_log("a,b\n1,2\n3,4\n5,6,7\n", "x.csv"); }),
            "x.csv:4: more cells than the header has columns (got 3, expected 2)");
}

TEST(Log, FileWithoutHeaderOrDataIsAnError) {
  EXPECT_NE(error_of([] { parse_log("", "e.csv"); }), "");
  EXPECT_NE(error_of([] { parse_log("1,2\n3,4\n", "n.csv"); }), "");
  EXPECT_NE(error_of([] { parse_log("a,b\n", "h.csv"); }), "");
}

TEST(Log, ColumnKeyIgnoresCaseUnitsAndPunctuation) {
  EXPECT_EQ(column_key("Cross-head [mm]"), "crosshead");
  EXPECT_EQ(column_key("Time (s)"), "time");
  EXPECT_EQ(column_key("FORCE 2"), "force2");
  EXPECT_EQ(split_unit("Force [kN]"), (std::pair<std::string, std::string>{"Force", "kN"}));
}

TEST(Log, WrittenLabviewTextReadsBack) {
  LogWriter w;
  for (int i = 0; i < 10; ++i) w.metadata.push_back("Key" + std::to_string(i) + "\tvalue " + std::to_string(i));
  w.columns = {"Time [s]", "Force [N]"};
  w.columns_data = {{0, 0.01, 0.02}, {1.25, -0.5, 3e-5}};
  const LogTable t = parse_log(to_log_text(w), "w.lvm");
  EXPECT_TRUE(t.format.decimal_comma);
  EXPECT_EQ(t.metadata.size(), 10u);
  EXPECT_EQ(t.numbers("force"), w.columns_data[1]);
}

TEST(CameraLog, ReadsFileNamesAndTimes) {
  const auto dir = test::scratch_dir("camera_log");
  std::ofstream(dir / "camera.csv") << "File,Time [s]\r\nimg_0000.tif,0.000\r\nimg_0001.tif,0.500\r\n";
  const auto frames = read_camera_log(dir / "camera.csv");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].file, "img_0001.tif");
  EXPECT_EQ(frames[1].time, 0.5);
}

TEST(FrameTimes, ComeFromTheLastNumberWithAUnitInTheFileName) {
  EXPECT_EQ(time_from_file_name("img_0003_t1.500s.tif"), 1.5);
  EXPECT_EQ(time_from_file_name("dir/cam-12500ms.png"), 12.5);
  EXPECT_EQ(time_from_file_name("frame_0007_2,25s.bmp"), 2.25);
  EXPECT_NE(error_of([] { time_from_file_name("img_0003.tif"); }), "");
}

TEST(Log, AFileWithAByteOrderMarkAndCrlfLineEndsReadsAsWithout) {
  const auto dir = test::scratch_dir("log_bom_crlf");
  std::ofstream(dir / "excel.csv", std::ios::binary)
      << "\xEF\xBB\xBFTime (s),Load (N)\r\n0.0,0.10\r\n0.5,2.5\r\n1.0,4.75\r\n";
  const LogTable t = read_log(dir / "excel.csv");
  EXPECT_EQ(t.columns.front(), "Time (s)");
  EXPECT_EQ(t.numbers("time"), (std::vector<double>{0, 0.5, 1.0}));
  EXPECT_EQ(t.numbers("load"), (std::vector<double>{0.1, 2.5, 4.75}));
}
