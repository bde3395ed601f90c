// The fuzzed bytes as a file: every reader under test takes a path. One file per process
// (libFuzzer runs inputs one after the other), in TMPDIR, removed at exit.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace fuzz {

class InputFile {
 public:
  /// A file named ncp-fuzz-PID<suffix> in TMPDIR (or /tmp); suffix e.g. ".msh".
  explicit InputFile(const std::string& suffix) {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::string(tmp && *tmp ? tmp : "/tmp") + "/ncp-fuzz-" +
            std::to_string(getpid()) + suffix;
  }
  ~InputFile() { std::remove(path_.c_str()); }
  /// Replaces the file's content with data[0, size); aborts if it cannot (not a finding
  /// of the reader).
  const std::string& Write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) ||
        std::fclose(f) != 0) {
      std::perror(path_.c_str());
      std::abort();
    }
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace fuzz
