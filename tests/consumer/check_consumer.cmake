# Installs Shatter from the build tree into a scratch prefix, builds the consumer project
# against it with find_package(shatter), and runs it. Called by CTest (see CMakeLists.txt).
foreach(var SHATTER_BUILD_DIR SHATTER_SOURCE_DIR WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_consumer.cmake needs -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()

run(${CMAKE_COMMAND} --install "${SHATTER_BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
run(${CMAKE_COMMAND} -S "${SHATTER_SOURCE_DIR}/tests/consumer/project" -B "${WORK_DIR}/build"
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_BUILD_TYPE=Release -DSHATTER_README=${SHATTER_SOURCE_DIR}/README.md)
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
# The README's program drops the chair: it must come to rest (under 5 cm/s after 3 s).
execute_process(COMMAND "${WORK_DIR}/build/readme_app" "${SHATTER_SOURCE_DIR}/demos/assets/chair.obj"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT rc EQUAL 0 OR NOT out MATCHES "body_added chair" OR NOT out MATCHES "chair rests at 0\\.0[0-4][0-9] m/s")
  message(FATAL_ERROR "the README's program failed or the chair did not come to rest (${rc})")
endif()
run("${WORK_DIR}/build/consumer_mpm")
