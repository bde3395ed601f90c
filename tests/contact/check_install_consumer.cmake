# Installs the build into a scratch prefix, builds examples/consumer (the README's C++
# quick start) against it with find_package(ncp COMPONENTS contact), solves its LCP, runs
# a scene with the installed contact library and with the installed contact-sim, and
# checks what they wrote. -DBUILD=<build dir> -DSOURCE=<source dir> -DWORK=<scratch dir>
set(prefix ${WORK}/install)
set(consumer_build ${WORK}/consumer_build)
file(REMOVE_RECURSE ${prefix} ${consumer_build} ${WORK}/scene)
file(MAKE_DIRECTORY ${WORK}/scene)
# A 2D block dropped onto a floor, 40 steps (output into out/, relative to the scene).
file(WRITE ${WORK}/scene/drop.toml [=[
name = "consumer-drop"
[geometry]
type = "rectangle"
size = [1.0, 0.2]
cells = [4, 2]
contact = ["ymin"]
[material]
young_modulus = 2e8
poisson_ratio = 0.3
density = 7800
[loads]
body_force = [0.0, -76518.0]
[obstacle]
type = "plane"
normal = [0.0, 1.0]
offset = -0.0001
[time]
dt = 1e-4
end_time = 4e-3
initial_state = "velocity"
initial_velocity = [0.0, -0.5]
[output]
directory = "out"
]=])
function(run_step expect_regex)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  WORKING_DIRECTORY ${WORK}/scene)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  if(NOT out MATCHES "${expect_regex}")
    message(FATAL_ERROR "${ARGN}: output does not match '${expect_regex}':\n${out}")
  endif()
  message(STATUS "${ARGN}: ${out}")
endfunction()
run_step("" ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix})
foreach(f bin/contact-sim include/contact/scene.hpp include/ncp/ncp.hpp
          share/ncp/examples/scenes/block_drop_2d.toml lib/cmake/ncp/ncpContactTargets.cmake)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()
run_step("" ${CMAKE_COMMAND} -S ${SOURCE}/examples/consumer -B ${consumer_build}
         -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release)
run_step("" ${CMAKE_COMMAND} --build ${consumer_build})
# x = (0.5, 0) solves the LCP (M x + q = (0, 1.5), x'(M x + q) = 0).
run_step("x = \\(0.5, 0\\)" ${consumer_build}/lcp)
run_step("consumer-drop: completed after 40 steps" ${consumer_build}/scene drop.toml)
if(NOT EXISTS ${WORK}/scene/out/steps.csv)
  message(FATAL_ERROR "the scene wrote no out/steps.csv")
endif()
file(STRINGS ${WORK}/scene/out/steps.csv rows)
list(LENGTH rows num_rows)
if(NOT num_rows EQUAL 41)
  message(FATAL_ERROR "steps.csv has ${num_rows} lines, expected a header and 40 steps")
endif()
run_step("completed" ${prefix}/bin/contact-sim drop.toml --quiet --no-output)
