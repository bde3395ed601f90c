# fc-solve as a user runs it: solve dense .dat problems, write the reactions, check them
# with numpy (check_reactions.py); a missing file and an unknown solver must exit with 2.
foreach(problem FrictionContact3D_1c Rover1039 Rover1040 Rover4396 FC3D_Example1)
  set(out ${WORK}/${problem}_reactions.txt)
  file(REMOVE ${out})
  execute_process(COMMAND ${FC_SOLVE} ${DATA}/${problem}.dat --tolerance 1e-10 --json
                          --reactions ${out}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE json)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "fc-solve ${problem}: exit ${rc}\n${json}")
  endif()
  string(JSON status GET "${json}" status)
  if(NOT status STREQUAL "converged")
    message(FATAL_ERROR "fc-solve ${problem}: status ${status}")
  endif()
  execute_process(COMMAND ${PYTHON} ${CHECKER} ${DATA}/${problem}.dat ${out} 1e-10
                  RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE text)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_reactions ${problem}: ${text}")
  endif()
  message(STATUS "${problem}: ${text}")
endforeach()
execute_process(COMMAND ${FC_SOLVE} ${DATA}/no_such_problem.dat RESULT_VARIABLE rc
                OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "fc-solve on a missing file exited with ${rc}, expected 2")
endif()
execute_process(COMMAND ${FC_SOLVE} ${DATA}/FrictionContact3D_1c.dat --solver nonsense
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "fc-solve --solver nonsense exited with ${rc}, expected 2")
endif()
# A global problem (Siconos text: M, H, q, b, mu): --global solves it through W and reports v
# with the residual of M v = q + H r; without --global the local reader refuses the file.
set(global_file ${DATA}/../gfc3d/GFC3D_TwoRods1.dat)
set(velocities ${WORK}/GFC3D_TwoRods1_velocities.txt)
file(REMOVE ${velocities})
execute_process(COMMAND ${FC_SOLVE} ${global_file} --global --json --velocities ${velocities}
                RESULT_VARIABLE rc OUTPUT_VARIABLE json)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fc-solve --global GFC3D_TwoRods1: exit ${rc}\n${json}")
endif()
string(JSON form GET "${json}" form)
string(JSON dofs GET "${json}" dofs)
string(JSON motion GET "${json}" global_motion_residual)
file(STRINGS ${velocities} v)
list(LENGTH v nv)
# (CMake compares no floating-point numbers: <= 1e-12 read off the exponent)
if(NOT form STREQUAL "global" OR NOT dofs EQUAL 54 OR NOT nv EQUAL 54 OR
   NOT (motion STREQUAL "0" OR motion MATCHES "e-(1[2-9]|[2-9][0-9]|[1-9][0-9][0-9])$"))
  message(FATAL_ERROR "fc-solve --global GFC3D_TwoRods1: form ${form}, ${dofs} dofs, ${nv} velocities, motion residual ${motion}")
endif()
execute_process(COMMAND ${FC_SOLVE} ${global_file} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--global")
  message(FATAL_ERROR "fc-solve on a global file without --global exited with ${rc}: ${err}")
endif()
message(STATUS "GFC3D_TwoRods1 --global: ${dofs} dofs, |M v - q - H r| / (1 + |q|) = ${motion}")
