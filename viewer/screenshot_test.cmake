# cmake -DCASE=screenshot|events|modes|bad_model -DXVFB_EXEC=... -DVIEWER=... [-DNURBSGL=... -DCHECK=... -DMODEL_A=...
#       -DMODEL_B=... -DMOVE=DX,DY,DZ -DTRIMMED_A=... -DTRIMMED_B=...] -DOUT=DIR -P screenshot_test.cmake
# The viewer's tests (viewer/CMakeLists.txt). Prints "SKIP: ..." (ctest reports Skipped) without xvfb-run.
cmake_policy(VERSION 3.16)  # if() compares quoted strings as strings (CMP0054)
if(NOT XVFB_EXEC)
  message("SKIP: xvfb-run not found (apt install xvfb xauth)")
  return()
endif()
file(MAKE_DIRECTORY ${OUT})

# The readout "clearance D +- B" in the viewer's stdout `out` must be the one of `nurbsgl clearance
# MODEL_A MODEL_B ARGN` (B's placement), digit for digit.
function(expect_cli_readout out)
  execute_process(COMMAND ${NURBSGL} clearance ${MODEL_A} ${MODEL_B} ${ARGN}
                  RESULT_VARIABLE crc OUTPUT_VARIABLE cli ERROR_VARIABLE cerr)
  list(JOIN ARGN " " arguments)
  message("nurbsgl clearance ${arguments}: ${cli}${cerr}")
  if(NOT crc EQUAL 0)
    message(FATAL_ERROR "nurbsgl clearance exited with ${crc}")
  endif()
  string(REGEX MATCH "clearance [^ ]+ \\+- [^ \n]+" viewer_readout "${out}")
  string(REGEX MATCH "clearance [^ ]+ \\+- [^ \n]+" cli_readout "${cli}")
  if(NOT viewer_readout OR NOT viewer_readout STREQUAL cli_readout)
    message(FATAL_ERROR "viewer '${viewer_readout}' != nurbsgl '${cli_readout}' (${arguments})")
  endif()
endfunction()

# The figures the regular expression `pattern` captures from the viewer's stdout `out` must be the
# JSON fields `fields` (a key path each, keys separated by spaces) of `nurbsgl ARGN --json`, as numbers
# (the viewer prints the shortest text of a double, the JSON parser 17 digits: EQUAL reads both).
function(expect_cli_figures out pattern fields)
  execute_process(COMMAND ${NURBSGL} ${ARGN} --json RESULT_VARIABLE crc OUTPUT_VARIABLE cli ERROR_VARIABLE cerr)
  list(JOIN ARGN " " arguments)
  if(NOT crc EQUAL 0)
    message(FATAL_ERROR "nurbsgl ${arguments} exited with ${crc}: ${cerr}")
  endif()
  if(NOT out MATCHES "${pattern}")
    message(FATAL_ERROR "the viewer printed no '${pattern}' (${out})")
  endif()
  set(k 1)
  foreach(field IN LISTS fields)
    string(REPLACE " " ";" path "${field}")
    string(JSON expected GET "${cli}" ${path})
    if(NOT "${CMAKE_MATCH_${k}}" EQUAL "${expected}")
      message(FATAL_ERROR "viewer ${field} ${CMAKE_MATCH_${k}} != nurbsgl ${arguments}: ${expected}")
    endif()
    message("viewer ${field} ${CMAKE_MATCH_${k}} = nurbsgl ${arguments}")
    math(EXPR k "${k} + 1")
  endforeach()
endfunction()

# viewer_check_screenshot on `png`: not blank, at least `min_segment` pixels of the segment's magenta
# (ARGN: more options of the check, e.g. --count R,G,B M).
function(check_picture png min_segment)
  execute_process(COMMAND ${CHECK} ${png} --min-segment ${min_segment} ${ARGN} RESULT_VARIABLE prc
                  OUTPUT_VARIABLE pout ERROR_VARIABLE perr)
  message("${pout}${perr}")
  if(NOT prc EQUAL 0)
    message(FATAL_ERROR "the picture check of ${png} failed")
  endif()
endfunction()

if(CASE STREQUAL "bad_model")
  # A malformed IGES file: the reader's message on stderr (and in the window), exit code 2, no crash.
  set(bad ${OUT}/bad.igs)
  file(WRITE ${bad} "this is not IGES\n")
  execute_process(COMMAND ${XVFB_EXEC} ${VIEWER} ${bad} --frames 2 --screenshot ${OUT}/bad.png
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
  # net, trim loops), tessellation, thickness, and clearance with every overlay; the culled boxes
  # also on the trimmed paper surface beside the 199x33 one ("trimmed": TRIMMED_A, TRIMMED_B).
  foreach(args "--mode;view;--pick;515,240" "--mode;tessellation" "--mode;thickness" "--overlay;cells,voxels,faces"
          "--overlay;culled" "trimmed;--overlay;culled")
    string(REPLACE ";" "_" name "${args}")
    string(REPLACE "," "_" name "${name}")
    set(png ${OUT}/mode${name}.png)
    set(models ${MODEL_A} ${MODEL_B})
    if(args MATCHES "^trimmed;")
      list(REMOVE_AT args 0)
      set(models ${TRIMMED_A} ${TRIMMED_B})
    endif()
    execute_process(COMMAND ${XVFB_EXEC} ${VIEWER} ${models} ${args} --frames 2 --screenshot ${png}
                            --width 640 --height 480
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("${args}: exit ${rc} ${out}${err}")
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "the viewer exited with ${rc} (${args})")
    endif()
    # The mesh and the thickness map are the CLI's on the same model (one front door each).
    if(args MATCHES "tessellation")
      expect_cli_figures("${out}" "mesh ([0-9]+) triangles, ([0-9]+) vertices" "triangles;vertices"
                         tessellate ${MODEL_A} --eps 1e-3 --relative)
    elseif(args MATCHES "thickness")
      expect_cli_figures("${out}" "thickness ([0-9]+) rays, ([0-9]+) hits, min ([^,]+), max ([^ \n]+)"
                         "rays;hits;thickness min;thickness max" thickness ${MODEL_A})
    endif()
    # A click at the middle of the free part of the window hits the sphere (the only face).
    if(args MATCHES "--pick" AND NOT err MATCHES "picked A face 0")
      message(FATAL_ERROR "the click at (515, 240) picked no face of A")
    endif()
    if(NOT args MATCHES "culled")
      check_picture(${png} 0)
      continue()
    endif()
    # Culled boxes (viewer/overlays.h): blocks kept (51,255,102) and pruned (255,51,51) at level 3
    # for the placement, and on the trimmed surface the blocks the trim culls (102,102,102).
    if(NOT err MATCHES "culled boxes at level 3: A [0-9]+ kept, [1-9][0-9]* pruned")
      message(FATAL_ERROR "no block of A pruned at level 3 (${args})")
    endif()
    set(counts --count 51,255,102 20 --count 255,51,51 20)
    if(name MATCHES "^trimmed")
      if(NOT err MATCHES "A [0-9]+ kept, [0-9]+ pruned, [1-9][0-9]* trim-culled")
        message(FATAL_ERROR "no block of the trimmed surface culled by its trim")
      endif()
      list(APPEND counts --count 102,102,102 20)
    endif()
    check_picture(${png} 0 ${counts})
  endforeach()
  return()
endif()

if(CASE STREQUAL "events")
  # Live input replayed (--events), B starting at --move-b MOVE. Script "move": a Shift + left drag
  # moves B (a plain left drag orbits the camera, the wheel zooms: B stays), so its placement must
  # be a move other than MOVE and no turn. Script "turn": a Shift + left drag, then a Shift + right
  # drag turns B: a rotation must be printed. Both: the readout equals `nurbsgl clearance` at the
  # printed placement digit for digit, and the picture shows the segment. A drag that does nothing
  # leaves B at MOVE (or unturned): fail.
  file(WRITE ${OUT}/events_move.txt "# viewer.events: input replayed one state per frame
drag shift-left 620 330 700 290 8
frame
drag left 800 400 780 400 4
wheel 1
frame 2
")
  file(WRITE ${OUT}/events_turn.txt "drag shift-left 620 330 700 290 8
drag shift-right 700 300 760 260 6
frame
")
  foreach(script move turn)
    set(png ${OUT}/events_${script}.png)
    file(REMOVE ${png})
    execute_process(COMMAND ${XVFB_EXEC} ${VIEWER} ${MODEL_A} ${MODEL_B} --events ${OUT}/events_${script}.txt
                            --move-b ${MOVE} --screenshot ${png} --width 960 --height 640
                    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    message("viewer, events_${script}.txt (exit ${rc}): ${out}${err}")
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "the viewer exited with ${rc}")
    endif()
    string(REGEX MATCH "placement (--rotate-b ([^ \n]+) )?--move-b ([^ \n]+)" placement "${out}")
    set(rotate "${CMAKE_MATCH_2}")
    set(move "${CMAKE_MATCH_3}")
    if(NOT placement OR move STREQUAL "${MOVE}")
      message(FATAL_ERROR "B did not move: '${placement}' (start --move-b ${MOVE})")
    endif()
    if(script STREQUAL "move" AND rotate)
      message(FATAL_ERROR "B turned under a Shift + left drag: '${placement}'")
    endif()
    if(script STREQUAL "turn" AND NOT rotate)
      message(FATAL_ERROR "B did not turn under a Shift + right drag: '${placement}'")
    endif()
    if(rotate)
      expect_cli_readout("${out}" --move-b ${move} --rotate-b ${rotate})
    else()
      expect_cli_readout("${out}" --move-b ${move})
    endif()
    check_picture(${png} 40)
  endforeach()
  return()
endif()

# A scripted run: B slides past A for 24 frames and stops at --move-b MOVE.
set(png ${OUT}/viewer.png)
file(REMOVE ${png})
string(TIMESTAMP t0 "%s")
execute_process(COMMAND ${XVFB_EXEC} ${VIEWER} ${MODEL_A} ${MODEL_B} --frames 24 --screenshot ${png} --move-b ${MOVE}
                --width 960 --height 640
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(TIMESTAMP t1 "%s")
math(EXPR seconds "${t1} - ${t0}")
message("viewer (${seconds} s, exit ${rc}): ${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the viewer exited with ${rc}")
endif()
# The readout of the last frame must be the CLI's at the same placement, digit for digit.
expect_cli_readout("${out}" --move-b ${MOVE})
# From the start view the torus hides part of the segment: that part dashed in dim magenta
# (153,38,153, viewer/app_render.cpp), the rest and the ends pure magenta.
check_picture(${png} 40 --count 153,38,153 20)
