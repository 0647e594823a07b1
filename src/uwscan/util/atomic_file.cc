#include "uwscan/util/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Why a write failed, as far as can be told afterwards: the stream keeps no
// error code, but a full disk shows in the free space, and a full disk or a
// file-size limit (ulimit -f) leave their errno behind.
std::string WriteFailureReason(const std::filesystem::path& path, int error) {
  const std::filesystem::path folder = path.parent_path().empty() ? "." : path.parent_path();
  std::error_code space_error;
  const std::filesystem::space_info space = std::filesystem::space(folder, space_error);
  if (!space_error && space.available < (std::uintmax_t{1} << 20)) return ": the disk is full";
  if (error == ENOSPC || error == EFBIG || error == EDQUOT || error == EIO) {
    return std::string(": ") + std::strerror(error);
  }
  return "";
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path, bool binary) : path_(std::move(path)) {
  temp_path_ = path_;
  temp_path_ += ".tmp-" + std::to_string(::getpid());
  out_.open(temp_path_, binary ? std::ios::out | std::ios::binary : std::ios::out);
  if (!out_.good()) {
    const int error = errno;
    // Say why: most often the folder was mistyped or not made yet.
    const std::filesystem::path folder = path_.parent_path().empty() ? "." : path_.parent_path();
    std::error_code ignored;
    UWS_CHECK(std::filesystem::is_directory(folder, ignored), path_.string(),
              ": cannot write: the folder ", folder.string(),
              std::filesystem::exists(folder, ignored) ? " is not a folder" : " does not exist");
    UWS_THROW(path_.string(), ": cannot open for writing: ", std::strerror(error));
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ignored;
    std::filesystem::remove(temp_path_, ignored);
  }
}

void AtomicFile::Finish() {
  if (finished_) return;
  out_.flush();
  const int write_error = errno;
  UWS_CHECK(out_.good(), path_.string(), ": write failed",
            WriteFailureReason(temp_path_, write_error));
  out_.close();
  UWS_CHECK(!out_.fail(), path_.string(), ": write failed", WriteFailureReason(temp_path_, errno));
  finished_ = true;
}

void AtomicFile::Commit() {
  Finish();
  std::error_code error;
  std::filesystem::rename(temp_path_, path_, error);
  UWS_CHECK(!error, path_.string(), ": cannot rename into place: ", error.message());
  committed_ = true;
}

OutputFolder::OutputFolder(const std::filesystem::path& path) {
  std::error_code error;
  for (std::filesystem::path p = path; !p.empty() && !std::filesystem::exists(p, error);
       p = p.parent_path()) {
    made_.push_back(p);
    if (p == p.parent_path()) break;
  }
  std::filesystem::create_directories(path, error);
  if (!error && std::filesystem::is_directory(path, error)) return;
  const std::string reason = error ? ": " + error.message() : std::string();
  RemoveMade();  // a parent made before the failure
  UWS_CHECK(false, path.string(), ": cannot create the output folder", reason);
}

OutputFolder::~OutputFolder() {
  if (!keep_) RemoveMade();
}

void OutputFolder::RemoveMade() {
  std::error_code ignored;
  for (const auto& p : made_) {
    if (!std::filesystem::remove(p, ignored)) break;  // not empty: it and those above stay
  }
}

StagedFolder::StagedFolder(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  UWS_USAGE_CHECK(!path.empty(), "--out: empty output folder name");
  std::error_code error;
  if (fs::exists(path, error)) {
    UWS_CHECK(fs::is_directory(path, error), path.string(), ": exists and is not a folder");
    UWS_CHECK(fs::is_empty(path, error), path.string(),
              ": output folder exists and is not empty (refusing to overwrite)");
  }
  final_path_ = fs::absolute(path).lexically_normal();
  temp_path_ = final_path_.parent_path() /
               (final_path_.filename().string() + ".tmp-" + std::to_string(::getpid()));
  fs::create_directories(temp_path_, error);
  UWS_CHECK(!error, path.string(), ": cannot create the output folder: ", error.message());
}

StagedFolder::~StagedFolder() {
  if (committed_) return;
  std::error_code ignored;
  std::filesystem::remove_all(temp_path_, ignored);
}

void StagedFolder::Commit() {
  std::error_code error;
  if (std::filesystem::exists(final_path_, error))
    std::filesystem::remove(final_path_, error);  // the empty folder
  std::filesystem::rename(temp_path_, final_path_, error);
  UWS_CHECK(!error, final_path_.string(), ": cannot move the output into place: ", error.message());
  committed_ = true;
}

bool SameExistingPath(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code error;
  return std::filesystem::exists(a, error) && std::filesystem::exists(b, error) &&
         std::filesystem::equivalent(a, b, error);
}

void RefuseOutputOntoInput(const std::string& option, const std::filesystem::path& output,
                           const std::vector<std::filesystem::path>& inputs) {
  for (const auto& input : inputs) {
    UWS_USAGE_CHECK(!SameExistingPath(input, output), option, " ", output.string(),
                    " is an input (", input.string(), "): it would be overwritten");
  }
}

void WriteFileAtomic(const std::filesystem::path& path, const std::string& contents) {
  StagedFiles file;
  file.Add(path, contents);
  file.Commit();
}

void StagedFiles::Add(const std::filesystem::path& path, const std::string& contents, bool binary) {
  auto file = std::make_unique<AtomicFile>(path, binary);
  file->stream() << contents;
  file->Finish();
  files_.push_back(std::move(file));
}

void StagedFiles::Commit() {
  for (const auto& file : files_) file->Commit();
  files_.clear();
}

}  // namespace uwscan
