// Atomic file output: write to a temporary name beside the target, rename on
// success, so a crash never leaves a truncated file under the final name.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace uwscan {

class AtomicFile {
 public:
  // Opens "<path>.tmp-<pid>" for writing; throws uwscan::Error naming the path.
  explicit AtomicFile(std::filesystem::path path, bool binary = false);
  ~AtomicFile();  // Removes the temporary if Commit() was not called.
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks the stream and closes it: the contents are on disk,
  // still under the temporary name (a job with several outputs finishes
  // them all before it commits any, so a full disk leaves none).
  void Finish();
  // Finishes (if not done yet) and renames onto the final path.
  void Commit();

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_path_;
  std::ofstream out_;
  bool finished_ = false;
  bool committed_ = false;
};

// A job's output folder: made (with any missing parents) on construction,
// throwing uwscan::Error naming it if it cannot be. If the job fails before
// Keep(), the folders it made are removed again, those left empty (the
// AtomicFiles in them remove their temporaries themselves): a failed run
// leaves nothing under the folder's name. A folder that was there before
// is never removed.
class OutputFolder {
 public:
  explicit OutputFolder(const std::filesystem::path& path);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  void Keep() { keep_ = true; }

 private:
  void RemoveMade();

  std::vector<std::filesystem::path> made_;  // innermost first
  bool keep_ = false;
};

// A folder written whole or not at all (a dataset): its files go into
// "<path>.tmp-<pid>" beside it, renamed onto `path` by Commit(). `path` must
// not exist or be an empty folder (nothing is overwritten); the temporary
// is removed if Commit() is not reached. Errors name `path`.
class StagedFolder {
 public:
  explicit StagedFolder(const std::filesystem::path& path);
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  // Where to write until Commit().
  const std::filesystem::path& path() const { return temp_path_; }
  void Commit();

 private:
  std::filesystem::path final_path_, temp_path_;
  bool committed_ = false;
};

// Writes a whole string atomically.
void WriteFileAtomic(const std::filesystem::path& path, const std::string& contents);

// Several outputs of one job: each written whole under its temporary name
// as it is added (AtomicFile::Finish), all renamed into place by Commit(),
// so a write that fails (a full disk) leaves none of them. Without Commit()
// every temporary is removed.
class StagedFiles {
 public:
  void Add(const std::filesystem::path& path, const std::string& contents, bool binary = false);
  void Commit();

 private:
  std::vector<std::unique_ptr<AtomicFile>> files_;
};

// Whether `a` and `b` both exist and are the same file or folder, by any
// path (false where either cannot be looked at).
bool SameExistingPath(const std::filesystem::path& a, const std::filesystem::path& b);

// Throws uwscan::UsageError, naming `option`, if `output` is one of the
// existing `inputs` (the same file by any path): writing it would replace
// what the command reads, such as a dataset's frames.csv or a frame.
void RefuseOutputOntoInput(const std::string& option, const std::filesystem::path& output,
                           const std::vector<std::filesystem::path>& inputs);

}  // namespace uwscan
