// libFuzzer target: the FCLIB HDF5 reader (ncp::fc::ReadFclib and ReadFclibSolution).
// Not in the CI list: libfclib calls exit() on an HDF5 error, which libFuzzer reports as a
// crash of every malformed file (docs/reliability.md).
#include <cstdint>
#include <exception>

#include "fuzz_input_file.hpp"
#include "ncp/fc/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile file(".hdf5");
  const std::string& path = file.Write(data, size);
  try {
    ncp::fc::ReadFclib(path);
    ncp::fc::ReadFclibSolution(path);
  } catch (const std::exception&) {
  }
  return 0;
}
