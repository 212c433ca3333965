// OutputDir (src/project/output/output_dir.cpp): staging, publication, stale files, a killed publication.
#include "tricot/project/output_dir.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
  const fs::path d = test::scratch_dir("output_dir_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

// The folder's files (relative, sorted), hidden records left out.
std::vector<std::string> files(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string rel = e.path().lexically_relative(dir).generic_string();
    if (e.is_regular_file() && rel.rfind(".tricot-", 0) != 0) out.push_back(rel);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(OutputDir, ARunWritesInStagingAndPublishesIntoTheFolder) {
  const fs::path dir = fresh("publish");
  OutputDir o(dir, "simulate");
  io::write_atomic(o.staging() / "a" / "step_0001.vtu", "1");
  io::write_atomic(o.staging() / "steps.csv", "s");
  EXPECT_TRUE(files(dir).empty());  // nothing visible before publishing
  o.publish();
  EXPECT_EQ(files(dir), (std::vector<std::string>{"a/step_0001.vtu", "steps.csv"}));
  EXPECT_FALSE(fs::exists(o.staging()));
  EXPECT_EQ(OutputDir::published(dir, "simulate"), (std::vector<std::string>{"a/step_0001.vtu", "steps.csv"}));
}

// Two runs of one verb into one folder at once would write and publish the same staging folder (a
// Slurm test ran two identifications of one project together, and one lost its checkpoint): the second
// is refused while the first runs, and runs once it has ended; another verb is not held back.
TEST(OutputDir, ASecondRunIntoTheSameFolderIsRefusedWhileTheFirstRuns) {
  const fs::path dir = fresh("lock");
  {
    OutputDir first(dir, "identify");
    try {
      OutputDir second(dir, "identify");
      ADD_FAILURE() << "a second run was let in";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("another tricot identify is writing this folder now"), std::string::npos)
          << e.what();
    }
    EXPECT_NO_THROW(OutputDir(dir, "simulate"));
  }
  EXPECT_NO_THROW(OutputDir(dir, "identify"));
}

TEST(OutputDir, ARerunRemovesTheEarlierRunsFilesItDoesNotWriteAgain) {
  const fs::path dir = fresh("stale");
  {
    OutputDir o(dir, "simulate");
    for (const char* f : {"t/step_0001.vtu", "t/step_0002.vtu", "t/step_0003.vtu", "t/steps.csv", "old/x.csv"})
      io::write_atomic(o.staging() / f, "old");
    o.publish();
  }
  io::write_atomic(dir / "notes.txt", "the user's");  // not a run's file: left alone
  OutputDir o(dir, "simulate");
  io::write_atomic(o.staging() / "t" / "step_0001.vtu", "new");
  io::write_atomic(o.staging() / "t" / "steps.csv", "new");
  o.publish();
  EXPECT_EQ(files(dir), (std::vector<std::string>{"notes.txt", "t/step_0001.vtu", "t/steps.csv"}));
  EXPECT_EQ(io::read_text(dir / "t" / "steps.csv"), "new");
  EXPECT_FALSE(fs::exists(dir / "old"));  // emptied folders go too
}

TEST(OutputDir, ARunKilledBeforePublishingLeavesTheEarlierRunWholeAndTheNextRunDropsItsFiles) {
  const fs::path dir = fresh("killed");
  {
    OutputDir o(dir, "dic");
    io::write_atomic(o.staging() / "points.csv", "earlier");
    o.publish();
  }
  {
    OutputDir killed(dir, "dic");  // never publishes: as a run killed mid-way
    io::write_atomic(killed.staging() / "points.csv", "killed");
    io::write_atomic(killed.staging() / "overlays" / "frame_0001.png", "killed");
  }
  EXPECT_EQ(files(dir), std::vector<std::string>{"points.csv"});
  EXPECT_EQ(io::read_text(dir / "points.csv"), "earlier");
  OutputDir next(dir, "dic");
  EXPECT_FALSE(fs::exists(next.staging()));  // the killed run's files are gone
  io::write_atomic(next.staging() / "points.csv", "next");
  next.publish();
  EXPECT_EQ(files(dir), std::vector<std::string>{"points.csv"});
  EXPECT_EQ(io::read_text(dir / "points.csv"), "next");
}

TEST(OutputDir, APublicationKilledHalfWayIsCompletedByTheNextRun) {
  const fs::path dir = fresh("journal");
  {
    OutputDir o(dir, "synth");
    io::write_atomic(o.staging() / "a.csv", "old");
    io::write_atomic(o.staging() / "b.csv", "old");
    o.publish();
  }
  // A publication killed after moving c.csv, before removing b.csv and moving a.csv.
  io::write_atomic(OutputDir::staging_of(dir, "synth") / "a.csv", "new");
  io::write_atomic(dir / "c.csv", "new");
  io::write_atomic(dir / ".tricot-synth.publishing.json",
                   R"({"verb": "synth", "remove": ["b.csv"], "move": ["a.csv", "c.csv"], "keep": []})");
  OutputDir next(dir, "synth");
  EXPECT_EQ(files(dir), (std::vector<std::string>{"a.csv", "c.csv"}));
  EXPECT_EQ(io::read_text(dir / "a.csv"), "new");
  EXPECT_FALSE(fs::exists(dir / ".tricot-synth.publishing.json"));
  EXPECT_EQ(OutputDir::published(dir, "synth"), (std::vector<std::string>{"a.csv", "c.csv"}));
}

TEST(OutputDir, APartialRunReplacesOnlyItsScope) {
  const fs::path dir = fresh("scope");
  {
    OutputDir o(dir, "simulate");
    for (const char* f : {"a/steps.csv", "a/step_0002.vtu", "b/steps.csv"}) io::write_atomic(o.staging() / f, "old");
    o.publish();
  }
  OutputDir o(dir, "simulate");
  io::write_atomic(o.staging() / "a" / "steps.csv", "new");
  o.publish({"a/"});
  EXPECT_EQ(files(dir), (std::vector<std::string>{"a/steps.csv", "b/steps.csv"}));
  EXPECT_EQ(OutputDir::published(dir, "simulate"), (std::vector<std::string>{"a/steps.csv", "b/steps.csv"}));
}

TEST(OutputDir, VerbsSharingAFolderKeepTheirOwnFiles) {
  const fs::path dir = fresh("verbs");
  OutputDir a(dir, "experiment");
  io::write_atomic(a.staging() / "sync.json", "{}");
  a.publish();
  OutputDir b(dir, "identify");
  io::write_atomic(b.staging() / "result.json", "{}");
  b.publish();
  EXPECT_EQ(files(dir), (std::vector<std::string>{"result.json", "sync.json"}));
}

TEST(OutputDir, ARecordNamingAFileOutsideTheFolderIsIgnored) {
  const fs::path dir = fresh("outside");
  io::write_atomic(dir.parent_path() / "output_dir_victim.txt", "keep");
  io::write_atomic(dir / ".tricot-dic.json",
                   R"({"verb": "dic", "files": ["../output_dir_victim.txt", "/etc/hostname"]})");
  OutputDir o(dir, "dic");
  io::write_atomic(o.staging() / "points.csv", "p");
  o.publish();
  EXPECT_TRUE(fs::exists(dir.parent_path() / "output_dir_victim.txt"));
}

TEST(OutputDir, AFileGivenAsTheFolderIsAFileError) {
  const fs::path dir = fresh("file");
  io::write_atomic(dir, "not a folder");
  EXPECT_THROW(OutputDir(dir, "dic"), FileError);
}

}  // namespace
}  // namespace tricot::project
