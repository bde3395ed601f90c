# Installs the build into a scratch prefix, builds tests/fc/consumer against it with
# find_package(ncp) and runs it on an FCLIB HDF5 problem and a Siconos .dat problem.
set(prefix ${WORK}/install)
set(consumer_build ${WORK}/consumer_build)
file(REMOVE_RECURSE ${prefix} ${consumer_build})
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD};--prefix;${prefix}"
    "${CMAKE_COMMAND};-S;${SOURCE}/consumer;-B;${consumer_build};-DCMAKE_PREFIX_PATH=${prefix};-DCMAKE_BUILD_TYPE=Release"
    "${CMAKE_COMMAND};--build;${consumer_build}"
    "${consumer_build}/fc_consumer;${DATA}/BoxesStack-local_problem_test.hdf5"
    "${consumer_build}/fc_consumer;${DATA}/Rover1039.dat"
    "${prefix}/bin/fc-solve;${DATA}/FrictionContact3D_1c.dat")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${step}\n${out}")
  endif()
endforeach()
message(STATUS "installed ncp::fc builds and solves: ${out}")
