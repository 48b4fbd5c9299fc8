# The installed-package test (ctest PackageConsumer): installs this build into a scratch prefix,
# configures and builds tests/package/consumer against it with find_package(isoquad), and runs
# it on data/fandisk.off; where the Python module was built, imports the installed one. Variables:
# BUILD_DIR, SOURCE_DIR, WORK_DIR, GENERATOR, FLAGS (the sanitizer flags the installed library was
# built with, which its user must link too), and PYTHON and PYTHON_DIR (the interpreter and the
# package's folder under the prefix) or empty.
file(REMOVE_RECURSE ${WORK_DIR})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGN}")
  endif()
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
# Only the public headers are installed.
file(GLOB_RECURSE headers RELATIVE ${WORK_DIR}/prefix/include ${WORK_DIR}/prefix/include/*)
list(SORT headers)
if(NOT headers STREQUAL "isoquad/error.hpp;isoquad/io.hpp;isoquad/quality.hpp;isoquad/remesh.hpp;isoquad/version.hpp")
  message(FATAL_ERROR "installed headers: ${headers}")
endif()
step(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/build -G ${GENERATOR}
     -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
     "-DCMAKE_CXX_FLAGS=${FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${FLAGS}")
step(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
step(${WORK_DIR}/build/consumer ${SOURCE_DIR}/data/fandisk.off ${WORK_DIR}/fandisk.obj 300)
if(NOT EXISTS ${WORK_DIR}/fandisk.obj)
  message(FATAL_ERROR "the consumer wrote no quads")
endif()
if(PYTHON)
  set(ENV{PYTHONPATH} ${WORK_DIR}/prefix/${PYTHON_DIR})
  unset(ENV{ISOQUAD_CLI})
  step(${PYTHON} -c "import isoquad, isoquad.dask, sys; p = '${WORK_DIR}/prefix/'; sys.exit(not (isoquad.__file__.startswith(p) and isoquad.dask.command_line() == p + 'bin/isoquad'))")
endif()
