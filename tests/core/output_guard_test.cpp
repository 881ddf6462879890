// Issue 37: the one check of every path a command writes (core/output_guard.h). A participant's
// folder here is made by hand (a log and a lock); the commands' own use of the guard, against a
// live session, is tested in tests/protocols/session/session_race_test.cpp.
#include "core/output_guard.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/input_error.h"
#include "core/session_files.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

const OutputTarget kFile{OutputKind::file};
const OutputTarget kImage{OutputKind::image_file};
const OutputTarget kFolder{OutputKind::folder};

struct Folders {
  fs::path root, participant, log;
};

Folders participant_folder(const std::string& name) {
  Folders folders;
  folders.root = testing::fresh_scratch_folder("output-guard-" + name);
  folders.participant = folders.root / "results" / "study" / "P001";
  fs::create_directories(folders.participant);
  folders.log = folders.participant / kSessionLogName;
  std::ofstream(folders.log) << "{}\n";
  std::ofstream(folders.participant / kSessionLockName) << "pid 1\n";
  return folders;
}

std::string refusal(const fs::path& path, const OutputTarget& target) {
  return output_target_refusal(path, "--out", target);
}

TEST(OutputGuard, EverySessionFileIsRefusedWhateverTheKindAndWhereverItIs) {
  const Folders folders = participant_folder("session-files");
  for (const OutputTarget& target : {kFile, kImage, kFolder}) {
    EXPECT_NE(refusal(folders.log, target).find("a session's log (events.jsonl)"), std::string::npos);
    EXPECT_NE(refusal(folders.participant / "session.lock", target).find("a session's lock"), std::string::npos);
    for (const SetAside kind : {SetAside::torn, SetAside::recovered, SetAside::replaced})
      EXPECT_NE(refusal(set_aside_path(folders.log, kind, 3), target).find("set aside"), std::string::npos);
  }
  // A log's name outside any participant folder (a copy, a new file) is a session's name all the same.
  EXPECT_NE(refusal(folders.root / "events.jsonl", kFile), "");
  // The message is one line naming the flag, the path and what was expected.
  const std::string message = refusal(folders.log, kFile);
  EXPECT_EQ(message.rfind("--out " + folders.log.string() + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("expected a path outside participant folders"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(OutputGuard, NothingInsideAParticipantsFolderButTheNamesACommandOwnsThere) {
  const Folders folders = participant_folder("inside");
  EXPECT_NE(refusal(folders.participant / "bench.json", kFile).find("inside the participant's folder"),
            std::string::npos);
  EXPECT_NE(refusal(folders.participant / "frames" / "x.png", kImage), "");  // at any depth
  EXPECT_NE(refusal(folders.participant, kFolder).find("a participant's folder"), std::string::npos);
  EXPECT_NE(refusal(folders.participant / "analysis", kFolder), "");
  // Export's own names beside the log, and nothing else; never as a folder, never deeper.
  const OutputTarget exported{OutputKind::file, {"trials.csv", "steps.csv"}};
  EXPECT_EQ(refusal(folders.participant / "trials.csv", exported), "");
  EXPECT_EQ(refusal(folders.participant / "steps.csv", exported), "");
  EXPECT_NE(refusal(folders.participant / "other.csv", exported), "");
  EXPECT_NE(refusal(folders.participant / "sub" / "trials.csv", exported), "");
  EXPECT_NE(refusal(folders.log, exported), "");
  // A folder holding a lock only (a run that has not written its first event yet) is a participant's.
  fs::remove(folders.log);
  EXPECT_NE(refusal(folders.participant / "x.json", kFile), "");
  // Nor is it one no more when only what its session set aside is left (a log removed under its
  // session: the lock goes at the session's end, events.jsonl.recovered-1 stays).
  fs::remove(folders.participant / kSessionLockName);
  std::ofstream(set_aside_path(folders.log, SetAside::recovered, 1)) << "{}\n";
  EXPECT_NE(refusal(folders.participant / "x.json", kFile).find("it holds events.jsonl.recovered-1"),
            std::string::npos);
  EXPECT_NE(refusal(folders.participant, kFolder), "");
  // The study folder beside participants is no participant's.
  EXPECT_EQ(refusal(folders.root / "results" / "study" / "trials.csv", kFile), "");
  EXPECT_EQ(refusal(folders.root / "results" / "study" / "analysis", kFolder), "");
}

TEST(OutputGuard, SymbolicLinksAreFollowedToWhereAWriteWouldLand) {
  const Folders folders = participant_folder("links");
  const fs::path outside = folders.root / "outside";
  fs::create_directories(outside);
  fs::create_symlink(folders.log, outside / "bench.json");
  EXPECT_NE(refusal(outside / "bench.json", kFile).find("resolves to " + folders.log.string()), std::string::npos);
  fs::create_directory_symlink(folders.participant, outside / "looks-harmless");
  EXPECT_NE(refusal(outside / "looks-harmless" / "out.png", kImage).find("participant's folder"), std::string::npos);
  EXPECT_NE(refusal(outside / "looks-harmless", kFolder), "");
  // A chain of links, the last dangling into the participant's folder.
  fs::create_symlink(folders.participant / "new.json", outside / "dangling.json");
  fs::create_symlink(outside / "dangling.json", outside / "chain.json");
  EXPECT_NE(refusal(outside / "chain.json", kFile), "");
  // A ".." after a link is taken from the link's target, as the kernel does: l/../P001 is the
  // participant's folder when l is a link to a folder beside it, whatever the text says.
  fs::create_directories(folders.root / "results" / "study" / "other");
  fs::create_directory_symlink(folders.root / "results" / "study" / "other", outside / "l");
  EXPECT_NE(refusal(outside / "l" / ".." / "P001", kFolder).find("resolves to " + folders.participant.string()),
            std::string::npos)
      << refusal(outside / "l" / ".." / "P001", kFolder);
  EXPECT_NE(refusal(outside / "l" / ".." / "P001" / "x.json", kFile), "");
  EXPECT_NE(refusal(outside / "l" / ".." / "P001" / "sub" / "..", kFolder), "");
  // A link to an ordinary file is an ordinary output.
  std::ofstream(outside / "plain.json") << "{}";
  fs::create_symlink(outside / "plain.json", outside / "to-plain.json");
  EXPECT_EQ(refusal(outside / "to-plain.json", kFile), "");
}

TEST(OutputGuard, WhatIsNotAFileOrAWritableFolderIsRefused) {
  const fs::path root = testing::fresh_scratch_folder("output-guard-kinds");
  EXPECT_NE(refusal("/dev/null", kFile).find("a character device"), std::string::npos);
  EXPECT_NE(refusal(root, kFile).find("a folder"), std::string::npos);
  EXPECT_NE(refusal(root / "missing" / "x.json", kFile).find("does not exist"), std::string::npos);
  EXPECT_NE(refusal(root / "x.unknown-image-format", kImage).find("unknown image format"), std::string::npos);
  std::ofstream(root / "file") << "x";
  EXPECT_NE(refusal(root / "file", kFolder).find("a file; expected a folder"), std::string::npos);
  EXPECT_NE(refusal(root / "file" / "below", kFolder).find("cannot be made"), std::string::npos);
  EXPECT_EQ(refusal(root / "new" / "deeper", kFolder), "");  // made when missing
  EXPECT_EQ(refusal(root / "x.png", kImage), "");
  EXPECT_NE(output_target_refusal("", "--json", kFile).find("--json: empty"), std::string::npos);
  EXPECT_THROW(check_output_target("/dev/null", "--json", kFile), InputError);
}

}  // namespace
}  // namespace fovlab
