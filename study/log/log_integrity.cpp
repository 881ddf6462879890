#include "study/log/log_integrity.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "study/log/event_log.h"
#include "study/log/log_events.h"
#include "core/digest.h"
#include "core/input_error.h"
#include "core/input_file.h"

namespace fovlab {

namespace fs = std::filesystem;

LabKey read_lab_key(const std::string& path, const std::string& results_dir) {
  const auto fail = [&](const std::string& what) { throw InputError("--lab-key " + path + ": " + what); };
  if (!results_dir.empty()) {
    std::error_code error;
    const fs::path key = fs::weakly_canonical(path, error);
    const fs::path results = fs::weakly_canonical(results_dir, error);
    const auto [results_end, key_end] = std::mismatch(results.begin(), results.end(), key.begin(), key.end());
    if (!error && results_end == results.end())
      fail("lies inside the results folder " + results_dir + " (keep the key where the logs' editors cannot read it)");
  }
  std::string bytes;
  try {
    bytes = read_input_file(path, "a lab key file of 16 to 4096 bytes (e.g. made by `openssl rand -hex 32`)", 4096);
  } catch (const InputError& error) {
    throw InputError(std::string("--lab-key ") + error.what());
  }
  if (bytes.size() < 16)
    fail("holds " + std::to_string(bytes.size()) + " bytes (expected 16 to 4096, e.g. made by `openssl rand -hex 32`)");
  return LabKey{bytes, sha256_hex("fovlab lab key\n", bytes).substr(0, 16)};
}

std::optional<LabKey> read_optional_lab_key(const std::string& path, const std::string& results_dir) {
  if (path.empty()) return std::nullopt;
  return read_lab_key(path, results_dir);
}

const char* log_status_name(LogStatus status) {
  switch (status) {
    case LogStatus::sealed:
      return "sealed";
    case LogStatus::unsealed:
      return "unsealed";
    case LogStatus::broken:
      return "broken";
  }
  return "broken";
}

bool LogIntegrity::macs_not_checked() const { return keyed && !mac_checked; }

std::string LogIntegrity::describe() const {
  switch (status) {
    case LogStatus::sealed:
      if (!keyed) return "sealed (no lab key: detects accidents and edits, not a forger who rewrites the chain)";
      return mac_checked ? "sealed (keyed, every MAC verified)"
                         : std::string("sealed (keyed; ") + macs_not_checked_note + ")";
    case LogStatus::unsealed:
      return "unsealed (" + reason + ")" + (macs_not_checked() ? std::string("; keyed, ") + macs_not_checked_note : "");
    case LogStatus::broken:
      return "broken at line " + std::to_string(line) + ": " + reason;
  }
  return reason;
}

std::string event_mac(const LabKey& key, const std::string& chain) { return hmac_sha256_hex(key.bytes, chain); }

void IntegrityTracker::header(const nlohmann::json& header, const std::string& path) {
  result_.schema_version = header_schema_version(header);
  const auto key_id = header.find(log_keys::lab_key_id);
  result_.keyed = key_id != header.end() && key_id->is_string();
  if (result_.keyed && key_ && key_id->get<std::string>() != key_->id)
    throw InputError(path + ":1: the log was sealed with lab key " + key_id->get<std::string>() +
                     ", but --lab-key is key " + key_->id + " (give the key the session ran with)");
  result_.mac_checked = result_.keyed && key_;
  // A reader given the lab key expects the lab's logs keyed with it: one that is not could have
  // had its key id and MACs stripped by someone rewriting it.
  key_not_used_ = key_ && !result_.keyed;
  last_was_seal_ = false;
}

void IntegrityTracker::mac(std::string_view chain, std::optional<std::string_view> mac, int line) {
  if (!result_.keyed) return;
  if (!mac) return broken(line, "the log is keyed but this event has no mac");
  if (key_ && *mac != event_mac(*key_, std::string(chain)))
    broken(line, "the event's MAC does not verify under the lab key (the log was changed after it was written)");
}

void IntegrityTracker::broken(int line, std::string reason) {
  if (broken_line_) return;
  broken_line_ = line;
  result_.line = line;
  result_.reason = std::move(reason);
}

void IntegrityTracker::seal(const nlohmann::json& seal_event, int line, const std::string& previous_chain,
                            int trials_complete) {
  last_was_seal_ = true;
  const auto count = seal_event.find(log_keys::trials_complete);
  if (count == seal_event.end() || !count->is_number_integer() || count->get<int64_t>() != trials_complete)
    broken(line, "the seal commits " + (count == seal_event.end() ? std::string("no") : count->dump()) +
                     " complete trials but the log holds " + std::to_string(trials_complete) + " up to it");
  const auto last_chain = seal_event.find(log_keys::last_chain);
  if (last_chain == seal_event.end() || !last_chain->is_string() || last_chain->get<std::string>() != previous_chain)
    broken(line, "the seal's last_chain is not the chain of the event before it");
}

LogIntegrity IntegrityTracker::finish(int chain_error_line, bool torn_tail) const {
  LogIntegrity result = result_;
  if (key_not_used_) {
    result.status = LogStatus::broken;
    result.line = 1;
    result.reason = "--lab-key was given but the log is not keyed (no lab_key_id): its events cannot be verified";
  } else if (chain_error_line && (!broken_line_ || chain_error_line <= *broken_line_)) {
    result.status = LogStatus::broken;
    result.line = chain_error_line;
    result.reason = "the event chain breaks here (a line was edited, removed, inserted or reordered)";
  } else if (broken_line_) {
    result.status = LogStatus::broken;
  } else if (result.schema_version < 2) {
    result.status = LogStatus::unsealed;
    result.reason = "schema " + std::to_string(result.schema_version) + " logs carry no seals";
  } else if (torn_tail) {
    result.status = LogStatus::unsealed;
    result.reason = "its last line is cut off: the session was interrupted while writing";
  } else if (!last_was_seal_) {
    result.status = LogStatus::unsealed;
    result.reason = "no seal at its end: the session was interrupted, or the log cut at a line boundary";
  } else {
    result.status = LogStatus::sealed;
    result.reason.clear();
  }
  return result;
}

}  // namespace fovlab
