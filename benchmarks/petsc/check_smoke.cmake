cmake_minimum_required(VERSION 3.18)
# Runs ncp-petsc-bench (configuration SOLVER) on 2 ranks on the grids 33 and 65 (nested
# iteration from 5, GMRES + PCMG)
# and checks from the CSV: every row converged, on 2 ranks, and the max-norm error against the
# exact solution falls by at least MIN_RATIO from the coarser grid to the finer (the measured
# order is about h^1.5, a ratio near 2.8). Called by ctest (benchmarks/petsc/CMakeLists.txt).
set(MIN_RATIO 1.5)
file(REMOVE ${CSV})
execute_process(COMMAND ${MPIEXEC} ${NUMPROC_FLAG} 2 --oversubscribe ${BENCH} --grids 33,65
                        --solvers ${SOLVER} --csv ${CSV}
  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "ncp-petsc-bench exited with ${result}:\n${output}")
endif()
file(STRINGS ${CSV} lines)
list(LENGTH lines num_lines)
if(NOT num_lines EQUAL 3)
  message(FATAL_ERROR "${CSV}: ${num_lines} lines, expected a header and 2 rows:\n${output}")
endif()
list(GET lines 0 header)
string(REPLACE "," ";" columns "${header}")
list(FIND columns ranks ranks_index)
list(FIND columns grid grid_index)
list(FIND columns error_vs_exact error_index)
list(FIND columns status status_index)
set(errors "")
foreach(row 1 2)
  list(GET lines ${row} line)
  string(REPLACE "," ";" fields "${line}")
  list(GET fields ${ranks_index} ranks)
  list(GET fields ${grid_index} grid)
  list(GET fields ${error_index} error)
  list(GET fields ${status_index} status)
  if(NOT ranks EQUAL 2 OR NOT status STREQUAL "converged")
    message(FATAL_ERROR "grid ${grid}: ranks ${ranks}, status '${status}' (expected 2, converged): ${line}")
  endif()
  list(APPEND errors ${error})
  message(STATUS "grid ${grid}: error_vs_exact ${error}")
endforeach()
list(GET errors 0 coarse_error)
list(GET errors 1 fine_error)
# CMake's math() is integer-only: the ratio is checked by Python.
execute_process(COMMAND ${PYTHON} -c
  "import sys; sys.exit(0 if float('${coarse_error}') >= ${MIN_RATIO} * float('${fine_error}') else 1)"
  RESULT_VARIABLE ratio_result)
if(NOT ratio_result EQUAL 0)
  message(FATAL_ERROR "error_vs_exact ${coarse_error} (grid 33) -> ${fine_error} (grid 65): "
                      "falls by less than ${MIN_RATIO}")
endif()
message(STATUS "error_vs_exact falls ${coarse_error} -> ${fine_error}, both rows converged on 2 ranks")
