#!/usr/bin/env bash
# Installs the Debian 12 packages this project needs, if missing. Idempotent and
# non-interactive; runs `apt-get update` once, and only when something must be installed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  ccache                   # rebuilds of unchanged sources are cache hits (scripts/build.sh)
  libeigen3-dev            # Eigen 3.4
  libsuitesparse-dev       # UMFPACK, KLU, CHOLMOD
  coinor-libipopt-dev      # Ipopt 3.11 (reference QP solver)
  catch2                   # Catch2 2.13 (tests)
  libgmsh-dev gmsh         # meshes (C++ API gmsh.h)
  libtoml11-dev            # scene files
  libboost-dev             # Boost.Geometry R-tree: mortar contact search (header only)
  nlohmann-json3-dev       # JSON output
  libcxxopts-dev           # command-line parsing
  python3-matplotlib       # figures (run with /usr/bin/python3)
  python3                  # input fuzz test tests/fuzz (run with /usr/bin/python3)
  libsiconos-numerics-dev  # peer solver for benchmarks
  libhdf5-dev              # HDF5 C library: the FCLIB reader of ncp::fc (serial flavour)
  libfclib-dev             # FCLIB reference reader: the oracle of tests/fc/test_fc_fclib
  pybind11-dev python3-dev # Python bindings (python/)
  python3-numpy python3-scipy python3-pytest   # Python packages' arrays, sparse Jacobians, tests
  python3-vtk9             # reads the ParaView output back in tests/python/test_vtk_output.py
  xvfb                     # a virtual X display: contact.vtu.render draws 3D snapshots with VTK off screen
  petsc-dev openmpi-bin    # PETSc 3.18 with MUMPS, hypre (ncp/petsc, examples/petsc, mpi tests)
  clang libclang-rt-14-dev # libFuzzer targets (scripts/fuzz.sh)
  clang-format             # the format check of scripts/test.sh
  python3-getfem           # GetFEM 5.4, the peer of benchmarks/contact/static_hertz_getfem.py (not the tests)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
