# Runs a demo and validates the scene.glb it writes with the Khronos glTF validator
# (tests/demos/gltf, installed by `npm ci` in scripts/test.sh): zero errors and zero warnings.
# With MAX_BYTES, the file must also be at most that big. Prints "SKIPPED:" (the test's skip
# pattern) when node or the validator is not installed.
if(NOT NODE OR NOT EXISTS "${VALIDATOR_DIR}/node_modules/gltf-validator/package.json")
  message("SKIPPED: the glTF validator is not installed (scripts/test.sh runs `npm ci --prefix tests/demos/gltf`; it needs npm)")
  return()
endif()
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${DEMO}" --quiet --out "${OUT}" ${ARGS} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DEMO} failed (${rc}): ${err}")
endif()
file(SIZE "${OUT}/scene.glb" bytes)
if(DEFINED MAX_BYTES AND bytes GREATER MAX_BYTES)
  message(FATAL_ERROR "scene.glb has ${bytes} bytes, more than ${MAX_BYTES}")
endif()
execute_process(COMMAND "${NODE}" "${VALIDATOR_DIR}/validate.mjs" "${OUT}/scene.glb" RESULT_VARIABLE rc OUTPUT_VARIABLE report)
message("${report}")
if(NOT rc EQUAL 0 OR NOT report MATCHES ": 0 errors, 0 warnings")
  message(FATAL_ERROR "scene.glb is not valid glTF 2.0")
endif()
