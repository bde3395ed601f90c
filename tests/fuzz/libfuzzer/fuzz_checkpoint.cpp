// libFuzzer target: the checkpoint reader of contact::Simulation
// (contact/src/checkpoint.hpp) and contact-sim's output positions stored in it. Every
// input must either parse or be refused with contact::CheckpointError (any std::exception
// counts); a crash, a sanitizer report, a hang or an allocation beyond the input's size
// is a finding.
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

#include "checkpoint.hpp"
#include "scene/scene_output.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const contact::internal::CheckpointData checkpoint =
        contact::internal::ParseCheckpoint(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    contact::internal::OutputPositions::Decode(checkpoint.application_data, "fuzz");
  } catch (const std::exception&) {
    // refused with a message: the expected outcome for most inputs
  }
  return 0;
}
