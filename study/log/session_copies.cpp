#include "study/log/session_copies.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>

#include "core/input_error.h"
#include "study/log/session_scan.h"

namespace fovlab {
namespace {

// The log sits in the folder its header's participant names (results/<study>/<participant>/events.jsonl).
bool in_own_folder(const SessionLogIdentity& log) {
  return std::filesystem::path(log.path).parent_path().filename() == log.participant;
}

size_t common_lines(const std::vector<std::string>& a, const std::vector<std::string>& b) {
  return static_cast<size_t>(
      std::mismatch(a.begin(), a.begin() + static_cast<long>(std::min(a.size(), b.size())), b.begin()).first -
      a.begin());
}

}  // namespace

std::vector<SessionCopy> find_session_copies(const std::vector<SessionLogIdentity>& logs) {
  std::map<std::string, std::vector<size_t>> by_session;
  for (size_t i = 0; i < logs.size(); ++i)
    if (!logs[i].session.empty()) by_session[logs[i].session].push_back(i);
  std::vector<SessionCopy> found;
  for (auto& [session, members] : by_session) {
    if (members.size() < 2) continue;
    // The chain of every line up to the first that does not hold (a log of the same session is rare:
    // read again only then).
    std::map<size_t, std::vector<std::string>> chains;
    for (size_t index : members) {
      try {
        chains[index] = scan_line_chains(logs[index].path);
      } catch (const InputError&) {}
    }
    std::erase_if(members, [&](size_t index) { return !chains.count(index); });
    if (members.size() < 2) continue;
    // The one used: intact, longest, in its own folder, first in path order.
    std::sort(members.begin(), members.end(), [&](size_t a, size_t b) {
      const SessionLogIdentity& x = logs[a];
      const SessionLogIdentity& y = logs[b];
      const auto rank = [](const SessionLogIdentity& log) {
        return std::make_tuple(log.first_chain_error_line != 0, -static_cast<long>(log.lines), !in_own_folder(log));
      };
      return rank(x) != rank(y) ? rank(x) < rank(y) : x.path < y.path;
    });
    const size_t kept = members.front();
    const SessionLogIdentity& used = logs[kept];
    std::optional<SessionCopy> kept_diverged;
    for (size_t position = 1; position < members.size(); ++position) {
      const size_t index = members[position];
      const SessionLogIdentity& log = logs[index];
      const size_t common = common_lines(chains[index], chains[kept]);
      SessionCopy copy;
      copy.log = index;
      copy.other = kept;
      if (common == chains[index].size()) {  // every line of it that holds is one of the used log's
        copy.reason = "a copy of " + used.path + " (the same session";
        if (log.first_chain_error_line)
          copy.reason += ", its chain broken at line " + std::to_string(log.first_chain_error_line);
        else if (log.lines < used.lines)
          copy.reason += ": its " + std::to_string(log.lines) + " lines are the first of " + std::to_string(used.lines);
        copy.reason += ")";
      } else if (common == chains[kept].size()) {  // longer than the used log, but broken past it
        copy.reason = "the same session as " + used.path + ", longer but its chain broken at line " +
                      std::to_string(log.first_chain_error_line) + " (the intact " + std::to_string(used.lines) +
                      " lines of the other are used)";
      } else {
        copy.kind = SessionCopy::Kind::diverged;
        copy.line = static_cast<int>(common) + 1;
        const auto parting = [&](const std::string& other) {
          return "the same session as " + other + " (the same header), but the two logs part at line " +
                 std::to_string(copy.line) + ": neither can be trusted alone";
        };
        copy.reason = parting(used.path);
        if (!kept_diverged) {
          kept_diverged = copy;
          kept_diverged->log = kept;
          kept_diverged->other = index;
          kept_diverged->reason = parting(log.path);
        }
      }
      found.push_back(std::move(copy));
    }
    if (kept_diverged) found.push_back(std::move(*kept_diverged));
  }
  std::sort(found.begin(), found.end(), [](const SessionCopy& a, const SessionCopy& b) { return a.log < b.log; });
  return found;
}

}  // namespace fovlab
