/// \file io.hpp
/// Readers of frictional contact problems: Siconos Numerics' `.dat` text format and FCLIB
/// HDF5 files (local problems, and global ones reduced to local form).
#pragma once

#include <optional>
#include <string>

#include "ncp/fc/global.hpp"
#include "ncp/fc/problem.hpp"

namespace ncp::fc {

/// Siconos' text format (FrictionContactProblem printed by frictionContact_printInFile):
///   dimension, n_c, the matrix W (NumericsMatrix: storage 0 dense, 1 sparse-block or
///   2 sparse, rows, columns, data), q, mu.
/// Dense:  m n, then m n entries column by column.
/// Sparse-block: nbblocks, block rows, block cols, cumulative row sizes, cumulative col
/// sizes, filled1, filled2, block-row pointers (filled1), block-column indices (filled2),
/// then per block its number and its entries column by column.
/// Sparse (2): the origin (1 triplet, 2 CSC, 3 CSR, 4 half triplet) and CSparse's
/// printout of the matrix (values with 6 significant digits, as Siconos writes them).
/// Throws std::runtime_error (with the file name and what was expected) on a malformed
/// file.
FrictionProblem ReadSiconosDat(const std::string& path);

/// Writes the problem in Siconos' text format with sparse-block storage (the blocks of W
/// that hold a nonzero, 17 significant digits), so that ReadSiconosDat and Siconos'
/// frictionContact_new_from_filename read it back. Throws std::runtime_error on I/O
/// failure.
void WriteSiconosDat(const FrictionProblem& problem, const std::string& path);

/// True when the FCLIB reader was compiled in (Debian libhdf5-dev found).
bool HaveFclib();

/// FCLIB HDF5 (read by ncp's own checked reader on the HDF5 C library, not libfclib): a
/// local problem as is; a global problem (M v = H r + f, u = H' v + w, without equality
/// constraints G) reduced to local form W = H' M^-1 H, q = H' M^-1 f + w (M factorized by
/// sparse Cholesky). Throws std::runtime_error naming the file, the dataset and the
/// defect when the file is not a well-formed FCLIB problem (missing dataset, wrong type
/// or length, sizes that disagree, a sparse index out of range, a non-finite value,
/// negative mu), when the problem has constraints (local R, global G) or is a
/// rolling-friction one, or when HDF5 is not compiled in. Never exits the process.
FrictionProblem ReadFclib(const std::string& path);

/// FCLIB HDF5 global problem as is (no reduction); throws std::runtime_error when the
/// file holds none, on a malformed file (as ReadFclib) or when HDF5 is not compiled in.
GlobalFrictionProblem ReadFclibGlobal(const std::string& path);
/// True when the FCLIB file holds a global problem and no local one (false without HDF5).
bool IsFclibGlobal(const std::string& path);

/// Siconos' text format of a global problem (globalFrictionContact_printInFile):
/// dimension, n_c, M and H as NumericsMatrix (any storage above), q (n), b (m), mu (n_c).
/// The text files do not say whether they hold a local or a global problem: the caller
/// chooses (fc-solve --global).
GlobalFrictionProblem ReadSiconosGlobalDat(const std::string& path);

/// A global problem: FCLIB HDF5 by signature (ReadFclibGlobal), else Siconos text
/// (ReadSiconosGlobalDat).
GlobalFrictionProblem ReadGlobalProblem(const std::string& path);

/// The stored reference solution r (/solution/r) of an FCLIB file, local or global;
/// nullopt when the file has none. Throws like ReadFclib on a malformed file or solution.
std::optional<Vector> ReadFclibSolution(const std::string& path);

/// By content: HDF5 (signature "\x89HDF") goes to ReadFclib, anything else to
/// ReadSiconosDat.
FrictionProblem ReadProblem(const std::string& path);

}  // namespace ncp::fc
