#include "study/log/participant_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <ctime>
#include <vector>

#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/session_files.h"

namespace fovlab {

namespace fs = std::filesystem;

namespace {

// mkdir of one level; true when this call made it. An existing entry must be a real folder.
bool make_real_folder(const fs::path& folder, const std::string& what) {
  bool made = false;
  if (::mkdir(folder.c_str(), 0755) == 0) made = true;
  else if (errno != EEXIST) throw FileError(folder.string(), "creating the " + what + " folder", errno);
  struct stat status {};
  if (::lstat(folder.c_str(), &status) != 0) throw FileError(folder.string(), "reading the " + what + " folder", errno);
  if (S_ISLNK(status.st_mode))
    throw InputError(folder.string() + ": the " + what +
                     " folder is a symbolic link (expected a real folder inside the results folder)");
  if (!S_ISDIR(status.st_mode)) throw InputError(folder.string() + ": not a folder (expected the " + what + " folder)");
  if (made) fsync_directory(folder.parent_path());
  return made;
}

std::string holder_text() {
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::time_t now = std::time(nullptr);
  char since[32];
  std::strftime(since, sizeof since, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return "pid " + std::to_string(::getpid()) + " on " + host + " since " + since;
}

std::string read_holder(int fd) {
  char text[256] = {};
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  std::string holder(text, got > 0 ? static_cast<size_t>(got) : 0);
  while (!holder.empty() && (holder.back() == '\n' || holder.back() == '\0')) holder.pop_back();
  return holder.empty() ? "holder unknown" : holder;
}

}  // namespace

ParticipantLock::ParticipantLock(const fs::path& results_dir, const std::string& study, const std::string& participant)
    : folder_(results_dir / study / participant), lock_path_(folder_ / kSessionLockName) {
  try {
    acquire(results_dir, study);
  } catch (...) {
    release();  // a failed start leaves nothing it made, and never touches a lock another process holds
    throw;
  }
}

void ParticipantLock::acquire(const fs::path& results_dir, const std::string& study) {
  // The results folder's missing ancestors, top down, made one mkdir at a time, each entry fsync'd
  // (remembered, so that a failed start can take them away again).
  std::vector<fs::path> missing;
  std::error_code error;
  for (fs::path folder = fs::absolute(results_dir).lexically_normal();
       !folder.empty() && !fs::exists(fs::symlink_status(folder, error)); folder = folder.parent_path()) {
    missing.push_back(folder);
    if (folder == folder.parent_path()) break;
  }
  for (auto folder = missing.rbegin(); folder != missing.rend(); ++folder) {
    if (::mkdir(folder->c_str(), 0755) == 0) {
      created_.push_back(*folder);
      fsync_directory(folder->parent_path());
    } else if (errno != EEXIST) {
      throw FileError(folder->string(), "creating the results folder", errno);
    }
  }
  if (make_real_folder(results_dir / study, "study")) created_.push_back(results_dir / study);
  if (make_real_folder(folder_, "participant")) created_.push_back(folder_);
  // The lock file is never removed while a run may hold it, except by its holder (release); a
  // process that opened a file its holder then removed sees another inode at the path and tries
  // again, so two processes never each hold a lock on a different file.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) throw FileError(lock_path_.string(), "opening the participant's lock", errno);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int reason = errno;
      const std::string holder = read_holder(fd);
      ::close(fd);
      if (reason == EWOULDBLOCK)
        throw InputError(folder_.string() + ": another fovlab process runs this participant (" + holder +
                         "); nothing was changed");
      throw FileError(lock_path_.string(), "locking the participant's folder", reason);
    }
    struct stat opened {
    }, named{};
    if (::fstat(fd, &opened) == 0 && ::lstat(lock_path_.c_str(), &named) == 0 && opened.st_ino == named.st_ino &&
        opened.st_dev == named.st_dev) {
      fd_ = fd;
      break;
    }
    ::close(fd);
  }
  if (fd_ < 0) throw InputError(lock_path_.string() + ": the lock file keeps being replaced; nothing was changed");
  // Who holds it, for the message of a second run: best effort (a full disk must not stop a run
  // that may only be resuming to seal).
  const std::string holder = holder_text() + "\n";
  if (::ftruncate(fd_, 0) == 0) (void)!::pwrite(fd_, holder.data(), holder.size(), 0);
}

void ParticipantLock::release() {
  // Only what this lock made, and only when the participant's folder holds no log (a log a failed
  // write left empty holds nothing): newest first, rmdir takes an empty folder only (another
  // participant may be in the study folder by now).
  if (!created_.empty() && created_.back() == folder_) {
    std::error_code error;
    const fs::path log = folder_ / kSessionLogName;
    const bool no_log = !fs::exists(fs::symlink_status(log, error)) || fs::file_size(log, error) == 0;
    if (no_log) {
      if (fd_ >= 0) {
        ::unlink(log.c_str());
        ::unlink(lock_path_.c_str());
      }
      for (auto folder = created_.rbegin(); folder != created_.rend(); ++folder) ::rmdir(folder->c_str());
      fsync_directory(created_.front().parent_path());
    }
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

ParticipantLock::~ParticipantLock() { release(); }

}  // namespace fovlab
