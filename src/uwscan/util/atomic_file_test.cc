#include "uwscan/util/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

class AtomicOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("uwscan_atomic_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(AtomicOutputTest, AFileAppearsOnlyOnCommit) {
  const fs::path path = root_ / "a.txt";
  {
    AtomicFile file(path);
    file.stream() << "half";
  }  // not committed: a failed job
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(root_));  // no temporary left either
  WriteFileAtomic(path, "whole\n");
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "whole");
}

// A file whose folder is not there says so (it said "cannot open for
// writing", which left the user to guess).
TEST_F(AtomicOutputTest, AMissingFolderIsNamed) {
  const auto message = [](const fs::path& path) {
    try {
      AtomicFile file(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(root_ / "nodir/e.json"), (root_ / "nodir/e.json").string() +
                                                 ": cannot write: the folder " +
                                                 (root_ / "nodir").string() + " does not exist");
  WriteFileAtomic(root_ / "file", "x");
  EXPECT_EQ(message(root_ / "file/e.json"), (root_ / "file/e.json").string() +
                                                ": cannot write: the folder " +
                                                (root_ / "file").string() + " is not a folder");
}

// A write that fails says why (it said only "write failed"): here a file-size
// limit, as `ulimit -f` sets, in place of a disk that fills up.
TEST_F(AtomicOutputTest, AFailedWriteSaysWhy) {
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // EFBIG, not a kill
  rlimit limit = old_limit;
  limit.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message = "no error";
  const fs::path path = root_ / "big.ply";
  try {
    AtomicFile file(path);
    file.stream() << std::string(1 << 16, 'x');
    file.Commit();
  } catch (const Error& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(message, path.string() + ": write failed: " + std::strerror(EFBIG));
  EXPECT_TRUE(fs::is_empty(root_));  // neither the file nor its temporary
}

// A job's outputs staged together: a second that fails to be written (a
// file-size limit here, as a disk filling up on it would) leaves the first
// unrenamed, with neither temporary; the files that were there stay.
TEST_F(AtomicOutputTest, StagedFilesAreRenamedAllOrNone) {
  WriteFileAtomic(root_ / "rig.yaml", "old\n");
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = old_limit;
  limit.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string message = "no error";
  try {
    StagedFiles files;
    files.Add(root_ / "rig.yaml", "new\n");
    files.Add(root_ / "report.json", std::string(1 << 16, 'x'));
    files.Commit();
  } catch (const Error& e) {
    message = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(message, (root_ / "report.json").string() + ": write failed: " + std::strerror(EFBIG));
  std::vector<fs::path> left;
  for (const auto& entry : fs::directory_iterator(root_)) left.push_back(entry.path());
  EXPECT_EQ(left, std::vector<fs::path>{root_ / "rig.yaml"});
  std::ifstream in(root_ / "rig.yaml");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "old");

  StagedFiles files;
  files.Add(root_ / "rig.yaml", "new\n");
  files.Add(root_ / "report.json", "{}\n");
  EXPECT_FALSE(fs::exists(root_ / "report.json"));  // not before Commit()
  files.Commit();
  std::ifstream renamed(root_ / "rig.yaml");
  std::getline(renamed, line);
  EXPECT_EQ(line, "new");
  EXPECT_TRUE(fs::exists(root_ / "report.json"));
}

// An output onto one of the inputs, by any path, is refused by option.
TEST_F(AtomicOutputTest, AnOutputOntoAnInputIsRefused) {
  WriteFileAtomic(root_ / "frames.csv", "x");
  fs::create_directories(root_ / "sub");
  EXPECT_NO_THROW(RefuseOutputOntoInput("--out", root_ / "new.tum", {root_ / "frames.csv"}));
  EXPECT_NO_THROW(RefuseOutputOntoInput("--out", root_ / "frames.csv", {root_ / "missing.csv"}));
  try {
    RefuseOutputOntoInput("--out", root_ / "sub/../frames.csv",
                          {root_ / "rig.yaml", root_ / "frames.csv"});
    ADD_FAILURE() << "an output onto an input";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--out " + (root_ / "sub/../frames.csv").string() +
                                         " is an input (" + (root_ / "frames.csv").string() +
                                         "): it would be overwritten");
  }
}

TEST_F(AtomicOutputTest, AFailedJobLeavesNoFolderItMade) {
  const fs::path out = root_ / "new" / "deeper";
  {
    OutputFolder folder(out);
    ASSERT_TRUE(fs::is_directory(out));
    AtomicFile file(out / "cloud.ply");
    file.stream() << "partial";
  }  // the job threw: neither the file nor the two folders it made remain
  EXPECT_FALSE(fs::exists(root_ / "new"));
  {
    OutputFolder folder(out);
    WriteFileAtomic(out / "report.json", "{}\n");
    folder.Keep();
  }
  EXPECT_TRUE(fs::exists(out / "report.json"));
}

TEST_F(AtomicOutputTest, AFolderThatWasThereOrIsNotEmptyStays) {
  const fs::path existing = root_ / "existing";
  fs::create_directories(existing);
  { OutputFolder folder(existing); }
  EXPECT_TRUE(fs::is_directory(existing));

  // Files written into a new folder before the failure (complete images,
  // say) keep it, and its parents.
  const fs::path out = root_ / "made" / "overlays";
  {
    OutputFolder folder(out);
    WriteFileAtomic(out / "000001.png", "x");
  }
  EXPECT_TRUE(fs::exists(out / "000001.png"));
}

TEST_F(AtomicOutputTest, AFileInTheWayIsAClearError) {
  const fs::path blocker = root_ / "blocker";
  WriteFileAtomic(blocker, "x");
  try {
    OutputFolder folder(blocker / "out");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("blocker/out: cannot create the output folder"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::is_regular_file(blocker));
  try {
    OutputFolder folder(blocker);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("blocker: cannot create the output folder"),
              std::string::npos)
        << e.what();
  }
}

// A dataset folder appears whole on Commit() or not at all, and never
// replaces one that holds something.
TEST_F(AtomicOutputTest, AStagedFolderAppearsWholeOrNotAtAll) {
  const fs::path out = root_ / "deeper" / "dataset";
  {
    StagedFolder staged(out);
    WriteFileAtomic(staged.path() / "rig.yaml", "x");
    EXPECT_FALSE(fs::exists(out));
  }  // failed before Commit()
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::is_empty(root_ / "deeper"));  // no temporary left
  {
    StagedFolder staged(out);
    WriteFileAtomic(staged.path() / "rig.yaml", "x");
    staged.Commit();
  }
  EXPECT_TRUE(fs::is_regular_file(out / "rig.yaml"));
  EXPECT_EQ(std::distance(fs::directory_iterator(root_ / "deeper"), fs::directory_iterator()), 1);
  try {
    StagedFolder staged(out);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              out.string() + ": output folder exists and is not empty (refusing to overwrite)");
  }
  fs::remove(out / "rig.yaml");  // an empty folder is taken
  {
    StagedFolder staged(out);
    WriteFileAtomic(staged.path() / "frames.csv", "y");
    staged.Commit();
  }
  EXPECT_TRUE(fs::is_regular_file(out / "frames.csv"));
}

}  // namespace
}  // namespace uwscan
