# Runs a demo, then opens its output in the browser viewer with headless Chromium
# (viewer_test.mjs): the scene is drawn with the bodies' colours and the counts shown are
# summary.json's. Prints "SKIPPED:" (the test's skip pattern) when node, the viewer's npm
# packages (scripts/install-npm-tools.sh) or Chromium are missing or Chromium cannot start.
if(NOT NODE OR NOT EXISTS "${VIEWER_DIR}/node_modules/puppeteer-core/package.json")
  message("SKIPPED: the viewer's npm packages are not installed (scripts/test.sh runs `npm ci --prefix demos/viewer`; it needs npm)")
  return()
endif()
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${DEMO}" --quiet --out "${OUT}" ${ARGS} RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${DEMO} failed (${rc}): ${err}")
endif()
execute_process(COMMAND "${NODE}" "${CMAKE_CURRENT_LIST_DIR}/viewer_test.mjs" "${VIEWER_DIR}" "${OUT}" "${VIEW_SCRIPT}"
                        "${OUT}/viewer.png"
                RESULT_VARIABLE rc OUTPUT_VARIABLE report ERROR_VARIABLE err)
message("${report}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the browser viewer does not show the run as summary.json describes it")
endif()
