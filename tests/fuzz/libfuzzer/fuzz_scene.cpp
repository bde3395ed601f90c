// libFuzzer target: the scene TOML reader (contact::LoadScene). Every input must either
// load or be refused with an exception derived from std::exception (SceneError names the
// file and key); a crash, a sanitizer report, a hang or an unbounded allocation is a
// finding.
#include <cstdint>
#include <exception>

#include "contact/scene.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile file(".toml");
  try {
    contact::LoadScene(file.Write(data, size));
  } catch (const std::exception&) {
    // refused with a message: the expected outcome for most inputs
  }
  return 0;
}
