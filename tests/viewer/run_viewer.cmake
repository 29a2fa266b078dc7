# ctest: shore-viewer under Xvfb with scripted input, then headless on the same frames,
# then the pixel comparison. -D VIEWER, XVFB_RUN, COMPARE, SCRIPT, OUT.
file(MAKE_DIRECTORY ${OUT})
set(common --scene vehicle --smoke --frames 40 --script ${SCRIPT} --width 1280 --height 720)
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1280x720x24" ${VIEWER} ${common}
                        --screenshot ${OUT}/window.png --report ${OUT}/window.json
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "shore-viewer under Xvfb exited with ${rc}")
endif()
execute_process(COMMAND ${VIEWER} ${common} --headless --screenshot ${OUT}/headless.png --report ${OUT}/headless.json
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "shore-viewer --headless exited with ${rc}")
endif()
execute_process(COMMAND ${COMPARE} ${OUT}/window.png ${OUT}/window.json ${OUT}/headless.png ${OUT}/headless.json
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the window's and the headless frames differ (see above)")
endif()
