#pragma once
// Whether a session log is as its writer left it (docs/log-schema.md, "Integrity"). Schema 2 logs
// chain every event with SHA-256 and end each run of the session (its end, and every pause) with a
// `seal` event that commits the number of complete trials and the chain so far. With a lab key (a
// file kept outside results/) every event also carries "mac", an HMAC-SHA-256 of its chain that
// only the key's holder can make, so no event can be rewritten without the key. Every reader
// (resume, replay, analyze, export) classifies a log as:
//   sealed   - chain unbroken, every seal consistent, the last event a seal;
//   unsealed - chain unbroken, every seal consistent, but the log does not end with a seal (the
//              session was interrupted by a crash or kill; or someone cut it at a line boundary);
//   broken   - the chain breaks, a seal contradicts the log, a MAC is missing or does not verify,
//              or a lab key was given and the log is not keyed with it.
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace fovlab {

// A lab's secret for keyed seals: the bytes of a file (16 to 4096 bytes, e.g. `openssl rand -hex 32`).
struct LabKey {
  std::string bytes;
  std::string id;  // the first 16 hex digits of a SHA-256 of the key: names it in logs, reveals nothing
};

// Reads a key file: a regular file of 16 to 4096 bytes, not inside `results_dir` when one is given
// (a key beside the logs would let whoever can edit them forge seals). Throws InputError naming the
// flag and the file.
LabKey read_lab_key(const std::string& path, const std::string& results_dir = "");
// The same for an optional --lab-key: none when `path` is empty.
std::optional<LabKey> read_optional_lab_key(const std::string& path, const std::string& results_dir = "");

enum class LogStatus { sealed, unsealed, broken };
const char* log_status_name(LogStatus status);

struct LogIntegrity {
  LogStatus status = LogStatus::unsealed;
  int line = 0;        // broken: the first line found wrong
  std::string reason;  // broken or unsealed: why, in words
  int schema_version = 0;
  bool keyed = false;        // the header names a lab key (lab_key_id)
  bool mac_checked = false;  // keyed and the key was given: every event's MAC verified
  // Keyed, but read without the key: what only the key proves is unproven (said so by every reader
  // that calls such a log sealed or unsealed; it stays usable).
  bool macs_not_checked() const;
  // One line for a person: "sealed (...)", "sealed (keyed; MACs not checked (no key given))",
  // "unsealed (...)", "broken at line N: ...".
  std::string describe() const;
};

inline constexpr const char* macs_not_checked_note = "MACs not checked (no key given)";

// The MAC of an event in a keyed log: HMAC-SHA-256 under the key of the event's chain (which
// commits the event's text and every event before it).
std::string event_mac(const LabKey& key, const std::string& chain);

// Fed a log's events in order by either reader; says at the end what the log is.
class IntegrityTracker {
 public:
  explicit IntegrityTracker(const LabKey* key) : key_(key) {}
  // The first event. Throws InputError "path:1: ..." when the log was sealed with another key.
  void header(const nlohmann::json& header, const std::string& path);
  // Every event, the header too, with its recomputed chain and its "mac" (none: absent or not a
  // string). Checks the MAC of a keyed log when the key was given.
  void mac(std::string_view chain, std::optional<std::string_view> mac, int line);
  // Any later event but a seal.
  void event() { last_was_seal_ = false; }
  // A seal at `line`; `previous_chain` is the chain of the event before it, `trials_complete` the
  // complete trials of the log up to it.
  void seal(const nlohmann::json& seal_event, int line, const std::string& previous_chain, int trials_complete);
  // The chain breaks at `line` (0: it does not); `torn_tail`: bytes after the last newline.
  LogIntegrity finish(int chain_error_line, bool torn_tail) const;

 private:
  void broken(int line, std::string reason);
  const LabKey* key_;
  LogIntegrity result_;
  bool last_was_seal_ = false;
  bool key_not_used_ = false;  // a key was given but the log is not keyed with any
  std::optional<int> broken_line_;
};

}  // namespace fovlab
