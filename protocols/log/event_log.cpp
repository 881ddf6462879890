#include "protocols/log/event_log.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/file_bytes.h"
#include "core/input_error.h"

namespace fovlab {

std::string event_chain(const std::string& previous_chain, const nlohmann::json& event_without_chain) {
  return ContentHash().add(previous_chain).add(event_without_chain.dump()).hex();
}

EventLogWriter::EventLogWriter(const std::string& path, std::string previous_chain, int64_t next_seq)
    : path_(path), chain_(std::move(previous_chain)), next_seq_(next_seq) {
  const bool created = ::access(path.c_str(), F_OK) != 0;
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(path + ": cannot open the session log for writing (" + std::strerror(errno) + ")");
  // One writer a log: a second `fovlab run` of the same participant would interleave events.
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(path + ": another fovlab process is writing this log");
  }
  if (created) fsync_directory(std::filesystem::path(path).parent_path());
}

EventLogWriter::~EventLogWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void EventLogWriter::append(nlohmann::json event) {
  const auto start = std::chrono::steady_clock::now();
  event["seq"] = next_seq_;
  event.erase("chain");
  const std::string chain = event_chain(chain_, event);
  event["chain"] = chain;
  const std::string line = event.dump() + "\n";
  size_t written = 0;
  while (written < line.size()) {
    const ssize_t result = ::write(fd_, line.data() + written, line.size() - written);
    if (result < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(path_ + ": writing the session log failed (" + std::strerror(errno) + ")");
    }
    written += static_cast<size_t>(result);
  }
  if (::fsync(fd_) != 0) throw std::runtime_error(path_ + ": fsync of the session log failed (" + std::strerror(errno) + ")");
  chain_ = chain;
  ++next_seq_;
  seconds_writing_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// Deepest array/object nesting of a line, strings skipped. nlohmann's parser recurses once per
// level, so a hostile line of a million '[' would overflow the stack before it could fail.
int nesting_depth(const std::string& line) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

constexpr int max_event_nesting = 32;  // events nest 3 levels deep; a header's config, 4

}  // namespace

EventLogFile parse_event_log(const std::string& bytes, const std::string& path) {
  EventLogFile log;
  log.path = path;
  const size_t last_newline = bytes.rfind('\n');
  log.intact_bytes = last_newline == std::string::npos ? 0 : last_newline + 1;
  if (log.intact_bytes < bytes.size()) log.torn_tail = bytes.substr(log.intact_bytes);
  size_t begin = 0;
  int line_number = 0;
  std::string chain;
  while (begin < log.intact_bytes) {
    const size_t end = bytes.find('\n', begin);
    ++line_number;
    const std::string line = bytes.substr(begin, end - begin);
    begin = end + 1;
    if (nesting_depth(line) > max_event_nesting)
      throw InputError(path + ":" + std::to_string(line_number) + ": not a session event (nested deeper than " +
                       std::to_string(max_event_nesting) + " levels)");
    nlohmann::json event = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (event.is_discarded() || !event.is_object())
      throw InputError(path + ":" + std::to_string(line_number) + ": not a JSON event (expected one JSON object a line)");
    if (!log.first_chain_error_line) {
      const auto seq = event.find("seq");
      const auto recorded = event.find("chain");
      bool consistent = seq != event.end() && seq->is_number_integer() &&
                        seq->get<int64_t>() == static_cast<int64_t>(log.events.size()) && recorded != event.end() &&
                        recorded->is_string();
      if (consistent) {
        nlohmann::json without_chain = event;
        without_chain.erase("chain");
        const std::string expected = event_chain(chain, without_chain);
        consistent = expected == recorded->get<std::string>();
        chain = expected;
      }
      if (!consistent) log.first_chain_error_line = line_number;
    }
    log.events.push_back(std::move(event));
    log.line_numbers.push_back(line_number);
  }
  log.last_chain = chain;
  return log;
}

EventLogFile read_event_log(const std::string& path) {
  const std::optional<std::string> bytes = read_file_bytes(path);
  if (!bytes) throw InputError(path + ": cannot open the session log (" + std::string(std::strerror(errno)) + ")");
  return parse_event_log(*bytes, path);
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
