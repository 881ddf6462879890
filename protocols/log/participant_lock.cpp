#include "protocols/log/participant_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <ctime>
#include <vector>

#include "core/atomic_file.h"
#include "core/input_error.h"

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
    throw InputError(folder.string() + ": the " + what + " folder is a symbolic link (expected a real folder inside the results folder)");
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
    : folder_(results_dir / study / participant), lock_path_(folder_ / "session.lock") {
  // The results folder's missing ancestors, top down, made one mkdir at a time (remembered, so that
  // a failed start can take them away again).
  std::vector<fs::path> missing;
  std::error_code error;
  for (fs::path folder = fs::absolute(results_dir).lexically_normal(); !folder.empty() && !fs::exists(fs::symlink_status(folder, error));
       folder = folder.parent_path()) {
    missing.push_back(folder);
    if (folder == folder.parent_path()) break;
  }
  for (auto folder = missing.rbegin(); folder != missing.rend(); ++folder)
    if (::mkdir(folder->c_str(), 0755) == 0) created_.push_back(*folder);
    else if (errno != EEXIST) throw FileError(folder->string(), "creating the results folder", errno);
  if (make_real_folder(results_dir / study, "study")) created_.push_back(results_dir / study);
  if (make_real_folder(folder_, "participant")) created_.push_back(folder_);
  // The lock file is never removed while a run may hold it, except by its holder (below); a
  // process that opened a file its holder then removed sees another inode at the path and tries
  // again, so two processes never each hold a lock on a different file.
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0) throw FileError(lock_path_.string(), "opening the participant's lock", errno);
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int reason = errno;
      const std::string holder = read_holder(fd_);
      ::close(fd_);
      fd_ = -1;
      if (reason == EWOULDBLOCK)
        throw InputError(folder_.string() + ": another fovlab process runs this participant (" + holder +
                         "); nothing was changed");
      throw FileError(lock_path_.string(), "locking the participant's folder", reason);
    }
    struct stat opened {}, named {};
    if (::fstat(fd_, &opened) == 0 && ::lstat(lock_path_.c_str(), &named) == 0 && opened.st_ino == named.st_ino &&
        opened.st_dev == named.st_dev)
      break;
    ::close(fd_);
    fd_ = -1;
  }
  if (fd_ < 0) throw InputError(lock_path_.string() + ": the lock file keeps being replaced; nothing was changed");
  const std::string holder = holder_text() + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, holder.data(), holder.size(), 0) != static_cast<ssize_t>(holder.size()))
    throw FileError(lock_path_.string(), "writing the participant's lock", errno);
}

ParticipantLock::~ParticipantLock() {
  if (fd_ < 0) return;
  if (!created_.empty() && created_.back() == folder_ && !fs::exists(folder_ / "events.jsonl")) {
    ::unlink(lock_path_.c_str());
    // Newest first; rmdir only takes an empty folder (another participant may be there by now).
    for (auto folder = created_.rbegin(); folder != created_.rend(); ++folder) ::rmdir(folder->c_str());
    fsync_directory(created_.front().parent_path());
  }
  ::close(fd_);
}

}  // namespace fovlab
