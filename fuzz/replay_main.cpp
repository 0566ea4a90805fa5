// A main() for a fuzz target without libFuzzer: runs the target's LLVMFuzzerTestOneInput on
// every file given and on every regular file of the folders given (not recursive, in name
// order), once each, no mutation. The replay build (fuzz/CMakeLists.txt) links it with
// the same fuzz_<target>.cpp the libFuzzer build uses, compiled by the normal compiler,
// so ctest replays each target's seed corpus (FuzzReplay.<target>), under ASan and UBSan
// in `make sanitize`.
//
// As under libFuzzer: arguments that start with '-' are flags, left to the target; its
// LLVMFuzzerInitialize, when it defines one, gets the whole command line before the first
// input runs (the inputs' paths are made absolute before it: fuzz_cli's changes the
// working folder); each input is passed in a heap block of exactly its size, so ASan sees
// a read past its end; the target's return value is ignored; a finding (fuzz::fail(), a
// crash, an escaping exception, a sanitizer report) ends the process abnormally. Before
// each input its path goes to stderr, so the last such line names the input of a finding.
//
// Exit status: 0 when every input ran, 77 when there was none (ctest's SKIP_RETURN_CODE),
// 2 when a file or folder given cannot be read.
#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

// POSIX files and folders rather than <filesystem> and <fstream>: this file is compiled in
// every build with the tests, and those headers take GCC seconds to parse.

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);
// Weak: most targets do not define it (libFuzzer's own stand-alone main does the same).
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

namespace {

// Adds the inputs named by `arg` to `inputs`, as absolute paths: the file itself, or a
// folder's regular files in name order. False when `arg` cannot be read.
bool collect(const char* arg, std::vector<std::string>& inputs) {
  char real[PATH_MAX];
  struct stat st;
  if (!realpath(arg, real) || stat(real, &st) != 0) return false;
  if (S_ISREG(st.st_mode)) {
    inputs.push_back(real);
    return true;
  }
  DIR* dir = S_ISDIR(st.st_mode) ? opendir(real) : nullptr;
  if (!dir) return false;
  std::vector<std::string> files;
  while (const dirent* e = readdir(dir)) {
    const std::string path = std::string(real) + "/" + e->d_name;
    if (stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) files.push_back(path);
  }
  closedir(dir);
  std::sort(files.begin(), files.end());
  inputs.insert(inputs.end(), files.begin(), files.end());
  return true;
}

bool run_one(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  std::string bytes;
  char buffer[65536];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) bytes.append(buffer, n);
  const bool read = !std::ferror(f);
  std::fclose(f);
  if (!read) return false;
  std::fprintf(stderr, "replay: %s (%zu bytes)\n", path.c_str(), bytes.size());
  const auto block = std::make_unique<uint8_t[]>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), block.get());
  LLVMFuzzerTestOneInput(block.get(), bytes.size());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] == '-') continue;  // the target's flag
    if (!collect(argv[i], inputs)) {
      std::fprintf(stderr, "replay: cannot read %s\n", argv[i]);
      return 2;
    }
  }
  if (LLVMFuzzerInitialize) LLVMFuzzerInitialize(&argc, &argv);
  if (inputs.empty()) {
    std::fprintf(stderr, "replay: skipped, no inputs\n");
    return 77;
  }
  for (const std::string& p : inputs)
    if (!run_one(p)) {
      std::fprintf(stderr, "replay: cannot read %s\n", p.c_str());
      return 2;
    }
  std::fprintf(stderr, "replay: %zu inputs, no finding\n", inputs.size());
  return 0;
}
