# Runs a command that must fail cleanly: non-zero exit code (not a signal) and a message on
# stderr containing EXPECT. Usage: cmake -DCMD="prog;arg;..." -DEXPECT=text -P expect_failure.cmake
execute_process(COMMAND ${CMD} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("exit: ${rc}\nstderr: ${err}")
if(rc EQUAL 0)
  message(FATAL_ERROR "expected a failure, got exit 0")
endif()
if(NOT rc MATCHES "^[0-9]+$" OR rc GREATER 125)
  message(FATAL_ERROR "expected a clean non-zero exit, got '${rc}' (a signal or crash)")
endif()
string(FIND "${err}" "${EXPECT}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "stderr does not contain '${EXPECT}'")
endif()
