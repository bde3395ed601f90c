// libFuzzer target: the Siconos .dat frictional contact reader (ncp::fc::ReadSiconosDat).
// Every input must give a validated problem or a std::runtime_error naming the file.
#include <cstdint>
#include <exception>

#include "fuzz_input_file.hpp"
#include "ncp/fc/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile file(".dat");
  try {
    ncp::fc::ReadSiconosDat(file.Write(data, size));
  } catch (const std::exception&) {
  }
  return 0;
}
