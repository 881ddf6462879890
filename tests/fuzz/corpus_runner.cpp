// Replays fuzz inputs through a libFuzzer harness without libFuzzer (the normal g++ build):
//   fovlab_config_corpus DIR|FILE...
// Runs LLVMFuzzerTestOneInput on every regular file of each directory (sorted by name) and on each
// file given directly; prints how many ran. Exits 1 when a directory has no file or an input could
// not be read, 2 without arguments. A bug in the code under test shows as an exception other than
// InputError (reported with the input's name, exit 1) or a crash.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

bool run_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    std::fprintf(stderr, "corpus_runner: %s: cannot open\n", path.c_str());
    return false;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) {
    std::fprintf(stderr, "corpus_runner: %s: cannot read\n", path.c_str());
    return false;
  }
  std::fprintf(stderr, "  %s (%zu bytes)\n", path.c_str(), bytes.size());
  try {
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
  } catch (const std::exception& error) {
    std::fprintf(stderr, "corpus_runner: %s: uncaught exception: %s\n", path.c_str(), error.what());
    return false;
  } catch (...) {
    std::fprintf(stderr, "corpus_runner: %s: uncaught exception of unknown type\n", path.c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DIR|FILE...\n", argv[0]);
    return 2;
  }
  int ran = 0;
  int failed = 0;
  for (int i = 1; i < argc; ++i) {
    const fs::path argument(argv[i]);
    std::error_code error;
    if (fs::is_directory(argument, error)) {
      std::vector<fs::path> files;
      for (const fs::directory_entry& entry : fs::directory_iterator(argument, error))
        if (entry.is_regular_file()) files.push_back(entry.path());
      if (error) {
        std::fprintf(stderr, "corpus_runner: %s: %s\n", argv[i], error.message().c_str());
        ++failed;
        continue;
      }
      if (files.empty()) {
        std::fprintf(stderr, "corpus_runner: %s: no input files (expected a corpus)\n", argv[i]);
        ++failed;
        continue;
      }
      std::sort(files.begin(), files.end());
      for (const fs::path& file : files) {
        ++ran;
        if (!run_file(file)) ++failed;
      }
    } else {
      ++ran;
      if (!run_file(argument)) ++failed;
    }
  }
  std::printf("corpus_runner: ran %d input%s, %d failed\n", ran, ran == 1 ? "" : "s", failed);
  return failed ? 1 : 0;
}
