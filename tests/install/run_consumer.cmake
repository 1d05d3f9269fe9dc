# Installs the build tree into a fresh prefix, builds tests/install/consumer against it with
# find_package(nurbsgl), and runs it on MODEL expecting EXPECT in its output. With PYTHON, the
# installed Python package (PREFIX/PYTHON_DIR) too: imported from there alone, it reads MODEL.
file(REMOVE_RECURSE ${WORK})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed: ${rc}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/build -DCMAKE_PREFIX_PATH=${WORK}/prefix
                        -DCMAKE_BUILD_TYPE=Release RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK}/build RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building the consumer failed:\n${out}\n${err}")
endif()
execute_process(COMMAND ${WORK}/build/consumer ${MODEL} RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "${EXPECT}")
  message(FATAL_ERROR "consumer: exit ${rc}, output '${out}', expected '${EXPECT}'")
endif()
if(PYTHON)
  set(site ${WORK}/prefix/${PYTHON_DIR})
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${site} ${PYTHON} -c
                          "import nurbsgl; m = nurbsgl.load('${MODEL}'); print(nurbsgl.__file__, 'faces', m.faces)"
                  WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "^${site}/nurbsgl/__init__.py faces 1")
    message(FATAL_ERROR "the installed Python package: exit ${rc}, output '${out}' ${err}")
  endif()
endif()
