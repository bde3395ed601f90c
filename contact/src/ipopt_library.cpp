#include "ipopt_library.hpp"

#include <dlfcn.h>

namespace contact::internal {
namespace {

// The runtime name of Debian's Ipopt 3.11 (package coinor-libipopt1v5).
constexpr const char* kIpoptSoname = "libipopt.so.1";

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// The library file that defines `symbol` in the global scope, or "" if none does.
std::string GlobalDefinition(const char* symbol) {
  void* entry = dlsym(RTLD_DEFAULT, symbol);
  Dl_info info;
  if (!entry || dladdr(entry, &info) == 0 || !info.dli_fname) return "";
  return info.dli_fname;
}

// RTLD_DEEPBIND: libipopt's dmumps_c (and libdmumps_seq's MPI_* stubs) bind in libipopt's
// own dependency tree before the global scope. AddressSanitizer's dlopen refuses the flag
// (the loaded libraries would bypass its malloc); then the global scope must hold no
// other MUMPS, or Ipopt would call it.
std::string OpenFlagsOrError(int* flags) {
  *flags = RTLD_NOW | RTLD_LOCAL;
  if (!kAddressSanitizer) {
    *flags |= RTLD_DEEPBIND;
    return "";
  }
  const std::string mumps = GlobalDefinition("dmumps_c");
  if (mumps.empty()) return "";
  return std::string("Ipopt cannot be isolated from the MUMPS of ") + mumps +
         " in this AddressSanitizer build (ASan refuses dlopen with RTLD_DEEPBIND, which "
         "keeps Ipopt on its own sequential MUMPS); run the Ipopt step in a build "
         "without -fsanitize=address";
}

template <typename Function>
bool Resolve(void* handle, const char* name, Function* out, std::string* error) {
  *out = reinterpret_cast<Function>(dlsym(handle, name));
  if (*out == nullptr && error->empty())
    *error = std::string(kIpoptSoname) + " has no symbol " + name +
             " (Ipopt's C interface, IpStdCInterface.h)";
  return *out != nullptr;
}

IpoptLibrary Load() {
  IpoptLibrary library;
  int flags = 0;
  library.error = OpenFlagsOrError(&flags);
  if (!library.error.empty()) return library;
  void* handle = dlopen(kIpoptSoname, flags);
  if (handle == nullptr) {
    const char* reason = dlerror();
    library.error = std::string("cannot load Ipopt (") + kIpoptSoname +
                    "): " + (reason ? reason : "unknown dlopen error") +
                    "; install Debian's coinor-libipopt1v5";
    return library;
  }
  // Kept loaded for the life of the process (Ipopt keeps static option registries).
  std::string& error = library.error;
  Resolve(handle, "CreateIpoptProblem", &library.create_problem, &error);
  Resolve(handle, "FreeIpoptProblem", &library.free_problem, &error);
  Resolve(handle, "AddIpoptStrOption", &library.add_string_option, &error);
  Resolve(handle, "AddIpoptNumOption", &library.add_number_option, &error);
  Resolve(handle, "AddIpoptIntOption", &library.add_integer_option, &error);
  Resolve(handle, "SetIntermediateCallback", &library.set_intermediate_callback, &error);
  Resolve(handle, "IpoptSolve", &library.solve, &error);
  return library;
}

}  // namespace

const IpoptLibrary& LoadIpopt() {
  static const IpoptLibrary library = Load();
  return library;
}

}  // namespace contact::internal
