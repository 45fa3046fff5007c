# Runs shatter-door at one ball speed and checks the dent the summary reports:
# MIN_DENT <= dent_depth_max <= MAX_DENT (m). if() compares numbers as doubles.
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${DEMO}" --quiet --out "${OUT}" --frames 40 --png-every 0 --ball-speed ${SPEED}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DEMO} failed (${rc}): ${err}")
endif()
file(READ "${OUT}/summary.json" summary)
string(JSON dent GET "${summary}" dent_depth_max)
string(JSON primitives GET "${summary}" primitives)
if(dent LESS ${MIN_DENT} OR dent GREATER ${MAX_DENT})
  message(FATAL_ERROR "ball at ${SPEED} m/s: dent ${dent} m, expected [${MIN_DENT}, ${MAX_DENT}]")
endif()
if(NOT primitives EQUAL 720)
  message(FATAL_ERROR "door has ${primitives} primitives, expected 720")
endif()
message(STATUS "ball at ${SPEED} m/s: dent ${dent} m")
