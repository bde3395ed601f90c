// The only place that talks to gmsh: a session guard and the copy of gmsh's current model
// into a plain Mesh.
#pragma once

#include <string>

#include "contact/mesh.hpp"

namespace contact::internal {

// Initializes gmsh quietly (General.Terminal = 0, no configuration files) on construction
// and finalizes it on destruction. gmsh keeps global state, so sessions are serialized by
// a process-wide mutex; callers must not hold their own gmsh session at the same time.
class GmshSession {
 public:
  explicit GmshSession(const std::string& model_name);
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// gmsh reports errors by throwing std::string; this turns them into std::runtime_error
// (or std::invalid_argument when the input is at fault) with `context` prepended.
template <class F>
void CallGmsh(const std::string& context, bool input_error, F&& f);

// Copies the mesh of gmsh's current model into a Mesh (rules in gmsh_reader.hpp). Does
// not validate orientation; `source` names the model in error messages.
Mesh ExtractGmshMesh(const std::string& source);

// Reverses the node order of every element with det(dx/dxi) < 0 at its centroid (used for
// generated meshes only, whose orientation is a gmsh convention, not user input).
void OrientElementsPositively(Mesh* mesh);

[[noreturn]] void ThrowGmshError(const std::string& context, bool input_error,
                                 const std::string& what);

template <class F>
void CallGmsh(const std::string& context, bool input_error, F&& f) {
  try {
    f();
  } catch (const std::string& what) {
    ThrowGmshError(context, input_error, what);
  }
}

}  // namespace contact::internal
