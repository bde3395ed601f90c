// libFuzzer target: the gmsh .msh reader (contact::ReadGmshMesh: the tag scanner, then
// gmsh itself, then the checks of the mesh). Every input must give a mesh or a
// std::invalid_argument naming the file.
#include <cstdint>
#include <exception>

#include "contact/gmsh_reader.hpp"
#include "fuzz_input_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::InputFile file(".msh");
  try {
    contact::ReadGmshMesh(file.Write(data, size));
  } catch (const std::exception&) {
  }
  return 0;
}
