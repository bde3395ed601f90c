# The link dependencies of the contact library that ship no CMake config on Debian 12,
# as imported targets: Gmsh::gmsh (libgmsh-dev) and PkgConfig::IPOPT (coinor-libipopt-dev
# 3.11, by pkg-config); plus toml11 and OpenMP. Used by contact/CMakeLists.txt and by the
# installed ncpConfig.cmake for find_package(ncp COMPONENTS contact) (the static contact
# library's private dependencies must be found again where it is linked).
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY NAMES gmsh)
if(GMSH_INCLUDE_DIR AND GMSH_LIBRARY AND NOT TARGET Gmsh::gmsh)
  add_library(Gmsh::gmsh UNKNOWN IMPORTED)
  set_target_properties(Gmsh::gmsh PROPERTIES
    IMPORTED_LOCATION "${GMSH_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
endif()
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND AND NOT TARGET PkgConfig::IPOPT)
  pkg_check_modules(IPOPT QUIET IMPORTED_TARGET ipopt)
endif()
find_package(toml11 QUIET)
find_package(OpenMP QUIET COMPONENTS CXX)
# Ipopt's headers are needed only by a build with NCP_WITH_IPOPT (its default: ON); the
# library is loaded at run time (contact/src/ipopt_library.hpp), never linked.
set(_ncp_contact_targets Gmsh::gmsh toml11::toml11 OpenMP::OpenMP_CXX)
if(NOT DEFINED NCP_WITH_IPOPT OR NCP_WITH_IPOPT)
  list(APPEND _ncp_contact_targets PkgConfig::IPOPT)
endif()
set(NcpContactDependencies_FOUND TRUE)
foreach(t IN LISTS _ncp_contact_targets)
  if(NOT TARGET ${t})
    set(NcpContactDependencies_FOUND FALSE)
  endif()
endforeach()
if(NOT NcpContactDependencies_FOUND)
  set(NcpContactDependencies_MISSING "")
  foreach(t IN LISTS _ncp_contact_targets)
    if(NOT TARGET ${t})
      list(APPEND NcpContactDependencies_MISSING ${t})
    endif()
  endforeach()
endif()
