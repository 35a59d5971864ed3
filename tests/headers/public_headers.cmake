# The public headers are the API: an embedder's translation unit that
# includes them compiles with nothing but hull/include, collision/include and
# Eigen on its include path, and reaches no internal header (collision/src:
# supports, Minkowski wrappers, GJK, EPA, SAT, the revolution paths).
#
# Run by ctest (tests/CMakeLists.txt) as
#   cmake -DCXX=... -DSOURCE_DIR=... -DBINARY_DIR=... -DEIGEN_DIRS=... -P public_headers.cmake
# For every public header, one translation unit including it alone is
# preprocessed with -H (GCC and Clang list every header they open); the test
# fails when one does not compile on the public include path alone or opens
# a hedra header outside it, and prints how many hedra headers each reaches.
cmake_minimum_required(VERSION 3.25)
foreach(var CXX SOURCE_DIR BINARY_DIR EIGEN_DIRS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "public_headers.cmake: -D${var}=... missing")
  endif()
endforeach()

set(public_roots ${SOURCE_DIR}/hull/include ${SOURCE_DIR}/collision/include)
set(include_flags)
foreach(dir IN LISTS public_roots EIGEN_DIRS)
  list(APPEND include_flags -I${dir})
endforeach()

file(GLOB_RECURSE headers RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/hull/include/*.hpp ${SOURCE_DIR}/collision/include/*.hpp)
list(SORT headers)
if(NOT headers)
  message(FATAL_ERROR "no public header found under ${SOURCE_DIR}")
endif()
file(MAKE_DIRECTORY ${BINARY_DIR})
set(failures 0)
foreach(header IN LISTS headers)
  string(REGEX REPLACE "^(hull|collision)/include/" "" spelled ${header})
  string(MAKE_C_IDENTIFIER ${spelled} stem)
  set(tu ${BINARY_DIR}/${stem}.cpp)
  file(WRITE ${tu} "#include <${spelled}>\nint main() { return 0; }\n")
  execute_process(COMMAND ${CXX} -std=c++17 -fsyntax-only -H ${include_flags} ${tu}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(SEVERE_ERROR "${spelled} does not compile on the public include path alone:\n${err}")
    math(EXPR failures "${failures} + 1")
    continue()
  endif()
  # -H lines: dots for the depth, a space, the path.
  string(REGEX MATCHALL "[^\n]*hedra/[^\n]*\\.hpp" opened "${err}")
  set(reached)
  foreach(line IN LISTS opened)
    string(REGEX REPLACE "^\\.+ " "" path "${line}")
    get_filename_component(path "${path}" REALPATH)
    list(APPEND reached ${path})
  endforeach()
  list(REMOVE_DUPLICATES reached)
  list(LENGTH reached count)
  set(outside)
  foreach(path IN LISTS reached)
    set(public FALSE)
    foreach(root IN LISTS public_roots)
      get_filename_component(root "${root}" REALPATH)
      string(FIND "${path}" "${root}/" at)
      if(at EQUAL 0)
        set(public TRUE)
      endif()
    endforeach()
    if(NOT public)
      list(APPEND outside ${path})
    endif()
  endforeach()
  if(outside)
    message(SEVERE_ERROR "${spelled} reaches internal headers: ${outside}")
    math(EXPR failures "${failures} + 1")
  endif()
  message(STATUS "${spelled}: ${count} hedra headers")
endforeach()
if(failures GREATER 0)
  message(FATAL_ERROR "${failures} public header(s) not self-contained on the public include path")
endif()
