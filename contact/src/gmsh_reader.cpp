#include "contact/gmsh_reader.hpp"

#include <gmsh.h>

#include <fstream>
#include <stdexcept>

#include "gmsh_model.hpp"

namespace contact {

Mesh ReadGmshMesh(const std::string& path) {
  if (!std::ifstream(path).good())
    throw std::invalid_argument("ReadGmshMesh: cannot open mesh file '" + path +
                                "' (expected a readable .msh file)");
  Mesh mesh;
  {
    internal::GmshSession session("contact_read");
    const std::string context = "ReadGmshMesh('" + path + "')";
    internal::CallGmsh(context, /*input_error=*/true, [&] {
      gmsh::open(path);
      mesh = internal::ExtractGmshMesh(context);
    });
  }
  ValidateMesh(mesh);
  return mesh;
}

}  // namespace contact
