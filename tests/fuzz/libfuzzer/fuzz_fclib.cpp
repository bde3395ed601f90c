// libFuzzer target: the FCLIB HDF5 reader (ncp::fc::ReadFclib and ReadFclibSolution).
// Reads through ncp's own checked HDF5 reader (ncp/fc/src/fclib_hdf5.cpp): a malformed
// file must end in an exception, never in exit() or a crash (docs/reliability-fclib.md).
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
