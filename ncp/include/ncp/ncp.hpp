/// \file ncp.hpp
/// Umbrella header of the ncp library.
#pragma once

#include "ncp/blas_threads.hpp"
#include "ncp/ncp_functions.hpp"
#include "ncp/problem.hpp"
#include "ncp/residuals.hpp"
#include "ncp/solver.hpp"
#include "ncp/square_function.hpp"
#include "ncp/types.hpp"
