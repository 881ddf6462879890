#pragma once
// One session counted once (export, analyze): a participant's folder copied under another name
// holds a log of the same session, which must not be counted twice. A session is known by its
// header: the chain of the header line commits its whole text (study, participant, seeds, config,
// device, start time...; log_lines.h EventChain::header_chain), which every schema has, so logs
// whose first lines have the same chain are logs of one session. Of those:
//   - one whose lines are all lines of another (the same chain at its last line: a copy, taken then
//     or later) is a copy of it, left out, the longer one used (of two equal ones, the one in the
//     folder its header's participant names, else the first in path order);
//   - a copy whose own chain breaks where it still agrees with the other is a damaged copy, left
//     out too; so is a longer log whose chain breaks after every line of an intact one (the intact
//     one, a backup taken mid-session, is used);
//   - two that part after a common start (both chains intact where they differ) are neither to be
//     trusted alone: both broken at the line where they part.
#include <cstddef>
#include <string>
#include <vector>

namespace fovlab {

// What is compared of each log: its path and what either reader says of it.
struct SessionLogIdentity {
  std::string path;
  std::string session;      // the header's chain; "" when it does not hold (compared with none)
  std::string participant;  // the header's
  int lines = 0;            // complete lines
  int first_chain_error_line = 0;
};

struct SessionCopy {
  enum class Kind { copy, diverged };
  Kind kind = Kind::copy;
  size_t log = 0;    // the log this is about (an index into the logs given)
  size_t other = 0;  // the log it is a copy of, or parts from
  int line = 0;      // diverged: the first line where the two differ
  std::string
      reason;  // "a copy of OTHER (the same session)"; "the same session as OTHER ..., but the logs part at line N: ..."
};

// Every copy and every divergence among `logs`, at most one entry a log (a copy's first). Logs of
// one session are read again for the chain of every line (session_scan.h scan_line_chains); one
// that cannot be read again is compared with none.
std::vector<SessionCopy> find_session_copies(const std::vector<SessionLogIdentity>& logs);

}  // namespace fovlab
