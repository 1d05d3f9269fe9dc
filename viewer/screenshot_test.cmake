# cmake -DCASE=screenshot|modes|bad_model -DXVFB_RUN=... -DVIEWER=... [-DNURBSGL=... -DCHECK=... -DMODEL_A=...
#       -DMODEL_B=... -DMOVE=DX,DY,DZ] -DOUT=DIR -P screenshot_test.cmake
# The viewer's tests (viewer/CMakeLists.txt). Prints "SKIP: ..." (ctest reports Skipped) without xvfb-run.
if(NOT XVFB_RUN)
  message("SKIP: xvfb-run not found (apt install xvfb xauth)")
  return()
endif()
file(MAKE_DIRECTORY ${OUT})

if(CASE STREQUAL "bad_model")
  # A malformed IGES file: the reader's message on stderr (and in the window), exit code 2, no crash.
  set(bad ${OUT}/bad.igs)
  file(WRITE ${bad} "this is not IGES\n")
  execute_process(COMMAND ${XVFB_RUN} -a ${VIEWER} ${bad} --frames 2 --screenshot ${OUT}/bad.png
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("exit ${rc}; stderr: ${err}")
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "a malformed model: exit code ${rc}, 2 expected")
  endif()
  string(FIND "${err}" "${bad}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the message does not name the file ${bad}")
  endif()
  if(NOT EXISTS ${OUT}/bad.png)
    message(FATAL_ERROR "no picture of the window with the message")
  endif()
  return()
endif()

if(CASE STREQUAL "modes")
  # Every other mode draws something and exits 0: a face picked by a click in view mode (control
  # net, trim loops), tessellation, thickness, and clearance with every overlay.
  foreach(args "--mode;view;--pick;515,240" "--mode;tessellation" "--mode;thickness" "--overlay;cells,voxels,culled")
    string(REPLACE ";" "_" name "${args}")
    string(REPLACE "," "_" name "${name}")
    set(png ${OUT}/mode${name}.png)
    execute_process(COMMAND ${XVFB_RUN} -a ${VIEWER} ${MODEL_A} ${MODEL_B} ${args} --frames 2 --screenshot ${png}
                            --width 640 --height 480
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("${args}: exit ${rc} ${out}${err}")
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "the viewer exited with ${rc} (${args})")
    endif()
    # A click at the middle of the free part of the window hits the sphere (the only face).
    if(args MATCHES "--pick" AND NOT err MATCHES "picked A face 0")
      message(FATAL_ERROR "the click at (515, 240) picked no face of A")
    endif()
    execute_process(COMMAND ${CHECK} ${png} --min-segment 0 RESULT_VARIABLE prc OUTPUT_VARIABLE pout)
    message("${pout}")
    if(NOT prc EQUAL 0)
      message(FATAL_ERROR "the picture check failed (${args})")
    endif()
  endforeach()
  return()
endif()

# A scripted run: B slides past A for 24 frames and stops at --move-b MOVE.
set(png ${OUT}/viewer.png)
file(REMOVE ${png})
string(TIMESTAMP t0 "%s")
execute_process(COMMAND ${XVFB_RUN} -a ${VIEWER} ${MODEL_A} ${MODEL_B} --frames 24 --screenshot ${png} --move-b ${MOVE}
                --width 960 --height 640
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(TIMESTAMP t1 "%s")
math(EXPR seconds "${t1} - ${t0}")
message("viewer (${seconds} s, exit ${rc}): ${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the viewer exited with ${rc}")
endif()
execute_process(COMMAND ${NURBSGL} clearance ${MODEL_A} ${MODEL_B} --move-b ${MOVE}
                RESULT_VARIABLE crc OUTPUT_VARIABLE cli ERROR_VARIABLE cerr)
message("nurbsgl clearance: ${cli}${cerr}")
if(NOT crc EQUAL 0)
  message(FATAL_ERROR "nurbsgl clearance exited with ${crc}")
endif()
# The readout of the last frame must be the CLI's at the same placement, digit for digit.
string(REGEX MATCH "clearance [^ ]+ \\+- [^ \n]+" viewer_readout "${out}")
string(REGEX MATCH "clearance [^ ]+ \\+- [^ \n]+" cli_readout "${cli}")
if(NOT viewer_readout OR NOT viewer_readout STREQUAL cli_readout)
  message(FATAL_ERROR "viewer '${viewer_readout}' != nurbsgl '${cli_readout}'")
endif()
execute_process(COMMAND ${CHECK} ${png} --min-segment 40 RESULT_VARIABLE prc OUTPUT_VARIABLE pout ERROR_VARIABLE perr)
message("${pout}${perr}")
if(NOT prc EQUAL 0)
  message(FATAL_ERROR "the picture check failed")
endif()
