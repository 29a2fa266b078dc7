# cmake -P script: install, build the consumer, run it; then check the precision guard.
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
endfunction()

set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
run(${CMAKE_COMMAND} --install "${SHORE_BINARY_DIR}" --prefix "${prefix}")

set(consumer_flags "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
if(SANITIZE)
  list(APPEND consumer_flags "-DCMAKE_CXX_FLAGS=-fsanitize=${SANITIZE}" "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=${SANITIZE}")
endif()

run(${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/good" -G "${CMAKE_GENERATOR}"
    "-DCMAKE_PREFIX_PATH=${prefix}" ${consumer_flags})
run(${CMAKE_COMMAND} --build "${WORK_DIR}/good")
run("${WORK_DIR}/good/shore_consumer")
message(STATUS "consumer built against the installed package and ran")

# Flip the application's precision: the link must fail, naming Shore's precision namespace.
execute_process(COMMAND ${CMAKE_COMMAND} -S "${CONSUMER_SOURCE_DIR}" -B "${WORK_DIR}/mismatch"
                        -G "${CMAKE_GENERATOR}" "-DCMAKE_PREFIX_PATH=${prefix}" -DFLIP_PRECISION=ON ${consumer_flags}
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "mismatch consumer failed to configure")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build "${WORK_DIR}/mismatch"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "a consumer built with the other btScalar precision linked: the guard failed")
endif()
if(NOT "${out}${err}" MATCHES "abi_f(32|64)")
  message(FATAL_ERROR "mismatch failed, but not at the precision guard:\n${out}\n${err}")
endif()
message(STATUS "precision mismatch rejected at link time")
