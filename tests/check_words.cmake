# The project speaks of the software alone: no development-process words in its sources, scripts and
# docs (history belongs in version control). Usage: cmake -DROOT=DIR [-DEXCLUDE=SUBDIR] [-DFIXTURE=ON]
# -P check_words.cmake fails listing every file:line that cites a tracker number, a work period or the
# instructions given. FIXTURE=ON first writes into ROOT a source that cites a tracker number (the
# check's own test: it must fail there); the words are assembled here so that no file holds them.
if(FIXTURE)
  set(cited "iss")
  string(APPEND cited "ue 12")
  file(WRITE "${ROOT}/cites_tracker.cpp" "// A comment citing ${cited}, which the check must refuse.\n")
endif()
file(GLOB_RECURSE files LIST_DIRECTORIES false
     "${ROOT}/*.cpp" "${ROOT}/*.h" "${ROOT}/*.glsl" "${ROOT}/*.py" "${ROOT}/*.sh" "${ROOT}/*.md" "${ROOT}/*.cmake"
     "${ROOT}/*CMakeLists.txt" "${ROOT}/.ci/*")
set(found "")
foreach(f IN LISTS files)
  file(RELATIVE_PATH rel "${ROOT}" "${f}")  # build trees and .git below ROOT are left out
  string(REGEX MATCH "(^|/)(build[^/]*|\\.git)/" in_build "${rel}")
  if(in_build)
    continue()
  endif()
  if(EXCLUDE AND f MATCHES "^${ROOT}/${EXCLUDE}/")
    continue()
  endif()
  file(STRINGS "${f}" lines REGEX "[Ii]ssue #?[0-9]+|[^A-Za-z][Ss]essions?[^A-Za-z]|[^A-Za-z][Bb]rief[^A-Za-z]")
  foreach(line IN LISTS lines)
    string(APPEND found "${f}: ${line}\n")
  endforeach()
endforeach()
if(found)  # the list as written (message(FATAL_ERROR) would wrap long lines), then the failure
  message(NOTICE "development-process words:\n${found}")
  message(FATAL_ERROR "development-process words found")
endif()
