#pragma once
// One participant's folder, results/<study>/<participant>/, owned by one process at a time. A
// `fovlab run` takes the lock before it reads, cuts or renames anything in the folder and holds it
// until it exits, so two runs of one participant cannot interleave, truncate each other's events or
// both start a session: the second changes nothing and exits 2 naming the first. The lock is an
// flock on `session.lock` in the folder, which also says who holds it (pid, host, since); the
// kernel drops it when the holder dies, however it dies. It is as good as the file system's flock:
// local file systems and NFS with its lock manager honour it between hosts; SMB/CIFS mounts and NFS
// without locking may not.
#include <filesystem>
#include <string>
#include <vector>

namespace fovlab {

class ParticipantLock {
 public:
  // Makes <results_dir>/<study>/<participant> when missing (mkdir is atomic: of two runs one
  // creates it, both then race for the lock) and takes its lock. Refuses (InputError) a study or
  // participant folder that is a symbolic link, and a folder another process holds: "...: another
  // fovlab process runs this participant (pid N on HOST since TIME)". Other failures are FileError.
  ParticipantLock(const std::filesystem::path& results_dir, const std::string& study, const std::string& participant);
  // Releases the lock. The folders this lock created (participant, study, results) are removed
  // again when the participant's holds no log (the run failed before its first event), so a failed
  // start leaves nothing behind.
  ~ParticipantLock();
  ParticipantLock(const ParticipantLock&) = delete;
  ParticipantLock& operator=(const ParticipantLock&) = delete;

  const std::filesystem::path& folder() const { return folder_; }

 private:
  void acquire(const std::filesystem::path& results_dir, const std::string& study);
  void release();

  std::filesystem::path folder_;
  std::filesystem::path lock_path_;
  int fd_ = -1;
  std::vector<std::filesystem::path> created_;  // the folders this lock made, oldest first
};

}  // namespace fovlab
