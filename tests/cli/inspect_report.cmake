# The inspection report in a real browser: a scan of the torus made by experiments/make_scan.py
# (PYTHON with the built module at PYTHONPATH), `nurbsgl inspect --align --report`, then headless
# Chromium opens the file: the page's script must run to its end (data-rendered on <body>, which
# needs a WebGL context and three.js), log no console error, and the screenshot must exist.
# Prints "SKIP: ..." (ctest reports Skipped) without chromium.
# cmake -DNURBSGL=... -DPYTHON=... -DPYTHONPATH=... -DBUILD=... -DMAKE_SCAN=... -DMODEL=... -DOUT=DIR
#       -P inspect_report.cmake
find_program(CHROMIUM NAMES chromium chromium-browser)
if(NOT CHROMIUM)
  message("SKIP: chromium not found (apt install chromium)")
  return()
endif()
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${PYTHONPATH} ${PYTHON} ${MAKE_SCAN} ${MODEL} ${OUT}/scan.ply
                        --points 20000 --noise 0.01 --angle 1 --shift 0.2 --build ${BUILD}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "make_scan.py: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${NURBSGL} inspect ${MODEL} ${OUT}/scan.ply --within 0.05,0.1 --max-distance 1 --align
                        --report ${OUT}/report.html
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}")
if(NOT rc MATCHES "^[01]$" OR NOT EXISTS ${OUT}/report.html)
  message(FATAL_ERROR "nurbsgl inspect --report: exit ${rc}\n${err}")
endif()
set(flags --headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader
          --enable-logging=stderr --v=0 --window-size=1100,900)
execute_process(COMMAND ${CHROMIUM} ${flags} --dump-dom file://${OUT}/report.html
                RESULT_VARIABLE rc OUTPUT_VARIABLE dom ERROR_VARIABLE log TIMEOUT 120)
if(NOT dom MATCHES "data-rendered=\"yes\"")
  message(FATAL_ERROR "the report's script did not run to its end (exit ${rc})\n${log}")
endif()
if(log MATCHES "Uncaught|CONSOLE[^\n]*[Ee]rror")
  message(FATAL_ERROR "the browser's console logged an error:\n${log}")
endif()
execute_process(COMMAND ${CHROMIUM} ${flags} --screenshot=${OUT}/report.png file://${OUT}/report.html
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE log TIMEOUT 120)
file(SIZE ${OUT}/report.png size)
if(NOT rc EQUAL 0 OR size LESS 20000)
  message(FATAL_ERROR "no screenshot of the report (exit ${rc}, ${size} bytes)\n${log}")
endif()
message("report rendered: ${OUT}/report.png (${size} bytes)")
