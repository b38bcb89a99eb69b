// OutputBatch (podid/core/io.hpp): the files of one command are published
// together or not at all, so a late failure (gnuplot, a full disk) neither
// leaves some of them nor replaces an earlier file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/core/io.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

namespace podid {
namespace {

using testing::ReadText;
using testing::TempDir;

std::vector<std::string> Sorted(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return names;
}

auto Text(const std::string& text) {
  return [text](std::ostream& os) { os << text; };
}

TEST(OutputBatch, NothingIsPublishedBeforeCommit) {
  const TempDir dir;
  const std::string old_file = dir.Write("old.csv", "old\n");
  {
    OutputBatch batch;
    WriteFileAtomically(old_file, Text("new\n"), &batch);
    WriteFileAtomically(dir.File("new.json"), Text("{}\n"), &batch);
    EXPECT_EQ(batch.staged(), 2u);
    // Staged: the targets are as before (the temporaries are hidden files).
    EXPECT_EQ(ReadText(old_file), "old\n");
    EXPECT_FALSE(std::filesystem::exists(dir.File("new.json")));
    batch.Commit();
    EXPECT_EQ(batch.staged(), 0u);
  }
  EXPECT_EQ(ReadText(old_file), "new\n");
  EXPECT_EQ(ReadText(dir.File("new.json")), "{}\n");
  EXPECT_EQ(Sorted(dir.Entries()), (std::vector<std::string>{"new.json", "old.csv"}));
}

TEST(OutputBatch, AnUncommittedBatchLeavesNothingAndReplacesNothing) {
  // The failure cwt --plot met: -o written, then gnuplot failed.
  const TempDir dir;
  const std::string old_file = dir.Write("ridge.csv", "old\n");
  try {
    OutputBatch batch;
    WriteFileAtomically(old_file, Text("new\n"), &batch);
    WriteFileAtomically(dir.File("scalogram.csv"), Text("1,2\n"), &batch);
    throw std::runtime_error("plot: gnuplot failed");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(ReadText(old_file), "old\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"ridge.csv"});
}

TEST(OutputBatch, AFailingWriterLeavesTheBatchsOtherFilesStaged) {
  const TempDir dir;
  {
    OutputBatch batch;
    WriteFileAtomically(dir.File("a.csv"), Text("a\n"), &batch);
    EXPECT_THROW(WriteFileAtomically(
                     dir.File("b.csv"),
                     [](std::ostream&) { throw std::runtime_error("no value"); }, &batch),
                 std::runtime_error);
    EXPECT_EQ(batch.staged(), 1u);
  }
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(OutputBatch, ARenameFailingMidwayPutsTheEarlierFilesBack) {
  namespace fs = std::filesystem;
  const TempDir dir;
  const std::string old_file = dir.Write("old.csv", "old\n");
  fs::create_hard_link(old_file, dir.File("other-name.csv"));
  struct stat before {};
  ASSERT_EQ(::stat(old_file.c_str(), &before), 0);
  {
    OutputBatch batch;
    WriteFileAtomically(old_file, Text("new\n"), &batch);
    WriteFileAtomically(dir.File("new.json"), Text("{}\n"), &batch);
    WriteFileAtomically(dir.File("b.csv"), Text("b\n"), &batch);
    WriteFileAtomically(dir.File("after.csv"), Text("c\n"), &batch);
    // Checked writable when staged; a folder there by commit time makes the
    // third rename fail (EISDIR), after two have succeeded.
    fs::create_directory(dir.File("b.csv"));
    try {
      batch.Commit();
      ADD_FAILURE() << "Commit did not throw";
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("b.csv"), std::string::npos) << message;
      EXPECT_NE(message.find("left as they were"), std::string::npos) << message;
    }
  }
  // The replaced file is the very file it was (same inode, both names), the
  // new one is gone, and no temporary or second name is left.
  EXPECT_EQ(ReadText(old_file), "old\n");
  struct stat after {};
  ASSERT_EQ(::stat(old_file.c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);
  EXPECT_EQ(after.st_nlink, 2u);
  EXPECT_EQ(Sorted(dir.Entries()),
            (std::vector<std::string>{"b.csv", "old.csv", "other-name.csv"}));
}

TEST(OutputBatch, ACommittedBatchLeavesNoSecondNames) {
  const TempDir dir;
  const std::string a = dir.Write("a.csv", "old a\n");
  const std::string b = dir.Write("b.csv", "old b\n");
  OutputBatch batch;
  WriteFileAtomically(a, Text("a\n"), &batch);
  WriteFileAtomically(b, Text("b\n"), &batch);
  batch.Commit();
  EXPECT_EQ(ReadText(a), "a\n");
  EXPECT_EQ(ReadText(b), "b\n");
  EXPECT_EQ(Sorted(dir.Entries()), (std::vector<std::string>{"a.csv", "b.csv"}));
  struct stat status {};
  ASSERT_EQ(::stat(a.c_str(), &status), 0);
  EXPECT_EQ(status.st_nlink, 1u);
}

TEST(OutputBatch, WriteCsvStagesInTheBatch) {
  const TempDir dir;
  TimeSeries series;
  series.time_s = Eigen::VectorXd::LinSpaced(3, 0.0, 0.2);
  series.values = Eigen::MatrixXd::Ones(3, 1);
  series.channel_names = {"y"};
  OutputBatch batch;
  WriteCsv(dir.File("y.csv"), series, &batch);
  EXPECT_FALSE(std::filesystem::exists(dir.File("y.csv")));
  batch.Commit();
  EXPECT_EQ(ReadCsv(dir.File("y.csv")).values, series.values);
}

TEST(OutputBatch, FoldersItCreatedGoWhenItIsNotCommitted) {
  const TempDir dir;
  std::filesystem::create_directory(dir.File("kept"));
  {
    OutputBatch batch;
    batch.CreateFolders(dir.File("kept/figs/run1/"));
    batch.CreateFolders(dir.File("kept/figs/run1"));  // again: nothing new
    WriteFileAtomically(dir.File("kept/figs/run1/signals.csv"), Text("t,y\n"), &batch);
  }
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"kept"});  // existed before: stays
  EXPECT_TRUE(std::filesystem::is_empty(dir.File("kept")));
  {
    OutputBatch batch;
    batch.CreateFolders(dir.File("kept/figs"));
    WriteFileAtomically(dir.File("kept/figs/signals.csv"), Text("t,y\n"), &batch);
    batch.Commit();
  }
  EXPECT_EQ(ReadText(dir.File("kept/figs/signals.csv")), "t,y\n");
}

TEST(OutputBatch, AnAdoptedFolderGoesWithItsStagedFiles) {
  // What a plot without gnuplot keeps (<png>.gnuplot-XXXXXX/plot.gp, data).
  const TempDir dir;
  const std::string kept = dir.File("fig.png.gnuplot-1");
  {
    OutputBatch batch;
    std::filesystem::create_directory(kept);
    batch.AdoptFolder(kept);
    WriteFileAtomically(kept + "/plot.gp", Text("plot 1\n"), &batch);
  }
  EXPECT_TRUE(dir.Entries().empty());
  {
    OutputBatch batch;
    std::filesystem::create_directory(kept);
    batch.AdoptFolder(kept);
    WriteFileAtomically(kept + "/plot.gp", Text("plot 1\n"), &batch);
    batch.Commit();
  }
  EXPECT_EQ(ReadText(kept + "/plot.gp"), "plot 1\n");
}

TEST(OutputBatch, ACommittedBatchTakesNoMoreFiles) {
  const TempDir dir;
  OutputBatch batch;
  batch.Commit();
  EXPECT_THROW(batch.Commit(), std::logic_error);
  EXPECT_THROW(WriteFileAtomically(dir.File("late.csv"), Text("x\n"), &batch), std::logic_error);
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(OutputBatch, DevicesAreWrittenAtOnce) {
  // A device cannot take a rename: it is written in place, as without a batch.
  OutputBatch batch;
  WriteFileAtomically("/dev/null", Text("x\n"), &batch);
  EXPECT_EQ(batch.staged(), 0u);
  EXPECT_THROW(WriteFileAtomically("/dev/full", Text(std::string(1 << 17, 'x')), &batch),
               std::runtime_error);
}

}  // namespace
}  // namespace podid
