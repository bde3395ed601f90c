# Imported targets for the SuiteSparse 5.x libraries we use (Debian's libsuitesparse-dev
# ships no CMake config): SuiteSparse::umfpack, SuiteSparse::klu, SuiteSparse::cholmod,
# SuiteSparse::spqr.
include(FindPackageHandleStandardArgs)
find_path(NcpSuiteSparse_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
set(_ncp_ss_libs umfpack klu cholmod spqr amd colamd camd ccolamd btf suitesparseconfig)
foreach(_lib IN LISTS _ncp_ss_libs)
  find_library(NcpSuiteSparse_${_lib}_LIBRARY NAMES ${_lib})
  list(APPEND _ncp_ss_required NcpSuiteSparse_${_lib}_LIBRARY)
endforeach()
find_package_handle_standard_args(NcpSuiteSparse REQUIRED_VARS NcpSuiteSparse_INCLUDE_DIR ${_ncp_ss_required})
if(NcpSuiteSparse_FOUND)
  foreach(_lib IN LISTS _ncp_ss_libs)
    if(NOT TARGET SuiteSparse::${_lib})
      add_library(SuiteSparse::${_lib} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${_lib} PROPERTIES
        IMPORTED_LOCATION "${NcpSuiteSparse_${_lib}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${NcpSuiteSparse_INCLUDE_DIR}")
    endif()
  endforeach()
  set_property(TARGET SuiteSparse::umfpack APPEND PROPERTY INTERFACE_LINK_LIBRARIES SuiteSparse::amd SuiteSparse::cholmod SuiteSparse::suitesparseconfig)
  set_property(TARGET SuiteSparse::klu APPEND PROPERTY INTERFACE_LINK_LIBRARIES SuiteSparse::amd SuiteSparse::colamd SuiteSparse::btf SuiteSparse::suitesparseconfig)
  set_property(TARGET SuiteSparse::spqr APPEND PROPERTY INTERFACE_LINK_LIBRARIES SuiteSparse::cholmod SuiteSparse::suitesparseconfig)
  set_property(TARGET SuiteSparse::cholmod APPEND PROPERTY INTERFACE_LINK_LIBRARIES SuiteSparse::amd SuiteSparse::colamd SuiteSparse::camd SuiteSparse::ccolamd SuiteSparse::suitesparseconfig)
endif()
