#include "study/log/event_log.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "study/log/log_events.h"
#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/digest.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/session_files.h"
#include "study/log/log_integrity.h"
#include "study/log/log_lines.h"

namespace fovlab {

std::string chain_of_text(const std::string& previous_chain, std::string_view text, int schema_version) {
  if (schema_version == 1) return ContentHash().add(previous_chain).add(text).hex();
  return sha256_hex(previous_chain, text);
}

std::string event_chain(const std::string& previous_chain, const nlohmann::json& event_without_chain,
                        int schema_version) {
  return chain_of_text(previous_chain, event_without_chain.dump(), schema_version);
}

EventLogWriter::EventLogWriter(const std::string& path, std::string previous_chain, int64_t next_seq,
                               const LabKey* lab_key)
    : path_(path), chain_(std::move(previous_chain)), next_seq_(next_seq), lab_key_(lab_key) {
  // Read and write: a log replaced under the writer is copied out of this descriptor (check_still_named).
  fd_ = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) throw FileError(path, "opening the session log for writing", errno);
  // One writer a log; the participant's lock (participant_lock.h) already ensures it, this flock
  // also keeps out a fovlab older than that lock.
  struct stat status {};
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(path + ": another fovlab process is writing this log");
  }
  if (::fstat(fd_, &status) != 0) {
    const int reason = errno;
    ::close(fd_);
    fd_ = -1;
    throw FileError(path, "reading the session log's size", reason);
  }
  size_ = status.st_size;
  device_ = status.st_dev;
  inode_ = status.st_ino;
  if (size_ == 0) fsync_directory(std::filesystem::path(path).parent_path());
}

EventLogWriter::~EventLogWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void EventLogWriter::append(nlohmann::json event) {
  const auto start = std::chrono::steady_clock::now();
  event[log_keys::seq] = next_seq_;
  event.erase(log_keys::chain);
  event.erase(log_keys::mac);
  if (event_kind(event) == SealEvent::kind) event[log_keys::last_chain] = chain_;
  const std::string chain = event_chain(chain_, event);
  event[log_keys::chain] = chain;
  if (lab_key_) event[log_keys::mac] = event_mac(*lab_key_, chain);
  const std::string line = event.dump() + "\n";
  // A failed write or fsync cuts the file back to its last complete line: a full disk leaves no
  // partial event behind (and a resume, once there is space, continues from the last one).
  const auto fail = [&](const char* operation) {
    const int reason = errno;
    if (::ftruncate(fd_, size_) == 0) ::fsync(fd_);
    throw FileError(path_, operation, reason);
  };
  size_t written = 0;
  while (written < line.size()) {
    const ssize_t result = ::write(fd_, line.data() + written, line.size() - written);
    if (result < 0) {
      if (errno == EINTR) continue;
      fail("writing the session log");
    }
    written += static_cast<size_t>(result);
  }
  if (::fsync(fd_) != 0) fail("fsync of the session log");
  size_ += static_cast<off_t>(line.size());
  chain_ = chain;
  ++next_seq_;
  check_still_named();
  seconds_writing_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// Copies the first `size` bytes of the open file `fd` into a new file `copy` (never an existing
// one), fsync'd with its folder entry. Returns 0, or the errno of what failed (the partial copy
// removed).
int copy_open_file(int fd, off_t size, const std::string& copy) {
  const int out = ::open(copy.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (out < 0) return errno;
  std::vector<char> buffer(1 << 16);
  int reason = 0;
  for (off_t done = 0; done < size && !reason;) {
    const ssize_t got = ::pread(fd, buffer.data(), std::min<off_t>(off_t(buffer.size()), size - done), done);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      reason = got < 0 ? errno : EIO;
      break;
    }
    for (ssize_t put = 0; put < got && !reason;) {
      const ssize_t wrote = ::write(out, buffer.data() + put, size_t(got - put));
      if (wrote < 0 && errno == EINTR) continue;
      if (wrote < 0) reason = errno;
      else put += wrote;
    }
    done += got;
  }
  if (!reason && ::fsync(out) != 0) reason = errno;
  ::close(out);
  if (reason) {
    ::unlink(copy.c_str());
    return reason;
  }
  fsync_directory(std::filesystem::path(copy).parent_path());
  return 0;
}

}  // namespace

void EventLogWriter::check_still_named() {
  struct stat named {};
  const bool same = ::stat(path_.c_str(), &named) == 0 && named.st_dev == device_ && named.st_ino == inode_;
  if (same) {
    // Written over in place (cp onto it, a shell's >, an editor that saves without a rename): the
    // same file, another size. What another program wrote is not this session's to cut; it stops.
    if (named.st_size == size_) return;
    throw InputError(path_ + ": another program wrote into the session log while this session wrote it (it holds " +
                     std::to_string(named.st_size) + " bytes where this session wrote " + std::to_string(size_) +
                     "); the session stops after " + std::to_string(next_seq_) +
                     " events and leaves the file as it is (a resume refuses it where its events no longer chain)");
  }
  const std::string now_there = std::filesystem::exists(std::filesystem::symlink_status(path_))
                                    ? "another program put another file at its name"
                                    : "its name no longer exists (removed or moved)";
  const std::string what = path_ + ": the session log was replaced while this session wrote it (" + now_there +
                           "); the session stops after " + std::to_string(next_seq_) + " events";
  // Every event is still in the file this writer holds open: copied out beside the log, the next
  // run resumes from it.
  int reason = ENOENT;
  for (int number = 1; number < 1000; ++number) {
    const std::string copy = set_aside_path(path_, SetAside::recovered, number).string();
    reason = copy_open_file(fd_, size_, copy);
    if (reason == EEXIST) continue;
    if (reason == 0)
      throw InputError(
          what + ". Every event it wrote is kept in " + copy +
          "; run the same command again to resume from it (whatever is then at the log's name is kept beside it as " +
          std::string(kSessionLogName) + ".replaced-N)");
    break;
  }
  struct stat held {};
  const bool still_linked = ::fstat(fd_, &held) == 0 && held.st_nlink > 0;
  throw InputError(what + ", and copying its events out beside it failed (" + std::strerror(reason) + "): " +
                   (still_linked ? "the file it wrote is still on disk under another name"
                                 : "the events it wrote are lost when this process ends"));
}

int header_schema_version(const nlohmann::json& header) {
  const auto schema = header.find(log_keys::schema_version);
  if (schema == header.end() || !schema->is_number_integer()) return 0;
  const int64_t version = schema->get<int64_t>();  // an unsigned above 2^63 reads as negative: refused too
  return version >= oldest_log_schema_version && version <= log_schema_version ? int(version) : 0;
}

size_t byte_order_mark_length(std::string_view bytes) { return bytes.starts_with("\xEF\xBB\xBF") ? 3 : 0; }

EventLogFile parse_event_log(const std::string& bytes, const std::string& path) {
  EventLogFile log;
  log.path = path;
  LogLines lines(bytes.data(), bytes.size(), bytes.size(), path);
  log.intact_bytes = lines.intact_bytes();
  if (log.intact_bytes < bytes.size()) log.torn_tail = bytes.substr(log.intact_bytes);
  EventChain chain;
  while (lines.next()) {
    nlohmann::json event = lines.whole_event();
    if (lines.number() == 1) log.schema_version = header_schema_version(event);
    const auto seq = event.find(log_keys::seq);
    const auto recorded = event.find(log_keys::chain);
    const auto mac = event.find(log_keys::mac);
    chain.line(
        lines,
        seq != event.end() && seq->is_number_integer() ? std::optional<int64_t>(seq->get<int64_t>()) : std::nullopt,
        recorded != event.end() && recorded->is_string()
            ? std::optional<std::string_view>(recorded->get_ref<const std::string&>())
            : std::nullopt,
        mac != event.end() && mac->is_string(), log.schema_version, &event);
    log.events.push_back(std::move(event));
    log.line_numbers.push_back(lines.number());
  }
  log.first_chain_error_line = chain.first_error_line();
  log.last_chain = chain.last_chain();
  log.header_chain = chain.header_chain();
  return log;
}

EventLogFile read_event_log(const std::string& path) {
  return parse_event_log(read_input_file(path, session_log_kind, max_log_bytes), path);
}

std::vector<std::string> find_session_logs(const std::string& path) {
  std::vector<std::string> logs;
  if (std::filesystem::is_regular_file(path)) return {path};
  if (!std::filesystem::is_directory(path)) throw InputError(path + ": no such log file or results folder");
  for (const auto& entry : std::filesystem::recursive_directory_iterator(path))
    if (entry.is_regular_file() && entry.path().filename() == "events.jsonl") logs.push_back(entry.path().string());
  std::sort(logs.begin(), logs.end());
  if (logs.empty()) throw InputError(path + ": no events.jsonl under this folder");
  return logs;
}

}  // namespace fovlab
