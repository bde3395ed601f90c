// libFuzzer target: the checkpoint reader of contact::Simulation
// (contact/src/checkpoint.hpp) and contact-sim's output positions stored in it. Every
// input must either parse or be refused with contact::CheckpointError (any std::exception
// counts); a crash, a sanitizer report, a hang or an allocation beyond the input's size
// is a finding. Each input is read twice: as it is (the header and checksum checks), and
// with its bytes after the 24-byte header taken as the payload of a file with a valid
// length and checksum (a mutation rarely keeps the checksum: this reaches the field
// checks).
#include <cstdint>
#include <exception>
#include <string>
#include <string_view>

#include "checkpoint.hpp"
#include "scene/scene_output.hpp"

namespace {

void Parse(std::string_view bytes) {
  try {
    const contact::internal::CheckpointData checkpoint =
        contact::internal::ParseCheckpoint(bytes, "fuzz");
    contact::internal::OutputPositions::Decode(checkpoint.application_data, "fuzz");
  } catch (const std::exception&) {
    // refused with a message: the expected outcome for most inputs
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Parse(bytes);
  constexpr size_t kHeader = 24;  // magic, version, byte-order mark, payload length
  if (size < kHeader) return 0;
  const std::string_view payload = bytes.substr(kHeader);
  const std::uint64_t length = payload.size();
  const std::uint64_t checksum = contact::internal::Fnv1a(payload);
  std::string file(bytes.substr(0, kHeader - 8));
  file.append(reinterpret_cast<const char*>(&length), sizeof length);
  file.append(payload);
  file.append(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  Parse(file);
  return 0;
}
