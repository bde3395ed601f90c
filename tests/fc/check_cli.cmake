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
