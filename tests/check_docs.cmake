# Fails when docs/parameters.md differs from `squama params --markdown`.
execute_process(COMMAND ${SQUAMA} params --markdown OUTPUT_FILE ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "squama params --markdown failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT} ${DOC} RESULT_VARIABLE diff)
if(NOT diff EQUAL 0)
  message(FATAL_ERROR "docs/parameters.md is stale: run scripts/update-docs and commit it "
                      "(diff ${OUT} ${DOC})")
endif()
