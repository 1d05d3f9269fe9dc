# ctest helper: `nurbsgl clash MODEL --json --csv CSV ARGS` on an assembly (NURBSGL = the
# executable, ARGS a ;-list) must exit 0 with PAIRS pairs, and each pair of CHECK_PAIRS ("I-J", a
# ;-list) must carry the distance, bound, faces and flags that `nurbsgl clearance MODEL MODEL
# --body-a I --body-b J --json` prints (the same text: the same doubles); the CSV must hold a
# header and one line per pair. Prints SKIPPED (the test's SKIP_REGULAR_EXPRESSION) when MODEL is
# missing.
if(NOT EXISTS "${MODEL}")
  message(STATUS "nurbsgl-cli-test SKIPPED: ${MODEL} is missing")
  return()
endif()
file(REMOVE "${CSV}")
set(env ${CMAKE_COMMAND} -E env XDG_CACHE_HOME=${CACHE_HOME})

# The stdout of a run that must exit 0.
function(run out_var)
  execute_process(COMMAND ${env} ${NURBSGL} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                  TIMEOUT 300)
  if(NOT rc STREQUAL "0")
    message(FATAL_ERROR "exit code ${rc}: nurbsgl ${ARGN}\n--- stdout ---\n${out}\n--- stderr ---\n${err}")
  endif()
  set(${out_var} "${out}" PARENT_SCOPE)
endfunction()

run(clash clash ${MODEL} --json --csv ${CSV} ${ARGS})
string(JSON pairs GET "${clash}" pairs)
string(JSON rows LENGTH "${clash}" results)
if(NOT pairs EQUAL PAIRS OR NOT rows EQUAL PAIRS)
  message(FATAL_ERROR "clash: ${pairs} pairs and ${rows} results, expected ${PAIRS}")
endif()

# Faces and flags through CMake's JSON; distance and bound as printed (CMake's JSON reading rounds
# doubles, and equal text is the same double: both print the shortest text that reads back exactly).
set(fields face_a face_b intersecting meets_tolerance)
foreach(pair IN LISTS CHECK_PAIRS)
  string(REPLACE "-" ";" ij "${pair}")
  list(GET ij 0 i)
  list(GET ij 1 j)
  run(reference clearance ${MODEL} ${MODEL} --body-a ${i} --body-b ${j} --json)
  set(found FALSE)
  math(EXPR last "${rows} - 1")
  foreach(k RANGE ${last})
    string(JSON a GET "${clash}" results ${k} body_a)
    string(JSON b GET "${clash}" results ${k} body_b)
    if(a EQUAL i AND b EQUAL j)
      set(found TRUE)
      foreach(f IN LISTS fields)
        string(JSON mine GET "${clash}" results ${k} ${f})
        string(JSON theirs GET "${reference}" ${f})
        if(NOT mine STREQUAL theirs)
          message(FATAL_ERROR "bodies ${i} and ${j}: clash says ${f} ${mine}, clearance ${theirs}")
        endif()
      endforeach()
    endif()
  endforeach()
  if(NOT found)
    message(FATAL_ERROR "clash: no row for bodies ${i} and ${j}")
  endif()
  # The row's keys are sorted: body_a, body_b, bound, box_distance, computed, distance.
  if(NOT clash MATCHES "\"body_a\": ${i},\n +\"body_b\": ${j},\n +\"bound\": ([^,\n]+),\n[^\n]+\n[^\n]+\n +\"distance\": ([^,\n]+),")
    message(FATAL_ERROR "clash: no bound and distance printed for bodies ${i} and ${j}")
  endif()
  set(mine "${CMAKE_MATCH_2} +- ${CMAKE_MATCH_1}")
  string(REGEX MATCH "\n  \"bound\": ([^,\n]+)," _ "${reference}")
  set(bound "${CMAKE_MATCH_1}")
  string(REGEX MATCH "\n  \"distance\": ([^,\n]+)," _ "${reference}")
  if(NOT mine STREQUAL "${CMAKE_MATCH_1} +- ${bound}")
    message(FATAL_ERROR "bodies ${i} and ${j}: clash says ${mine}, clearance ${CMAKE_MATCH_1} +- ${bound}")
  endif()
  message(STATUS "bodies ${i} and ${j}: ${mine} as clearance")
endforeach()

file(STRINGS "${CSV}" lines)
list(LENGTH lines count)
list(GET lines 0 header)
math(EXPR expected "${PAIRS} + 1")
if(NOT count EQUAL expected OR NOT header MATCHES "^body_a,name_a,body_b,name_b,status,distance,bound,")
  message(FATAL_ERROR "${CSV}: ${count} lines (expected ${expected}), header '${header}'")
endif()
message(STATUS "ok: ${pairs} pairs, ${count} CSV lines")
