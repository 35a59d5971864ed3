# Driver of the downstream ctest tests (cmake -P). Arguments (-D):
#   STEP          install | find_package | subdirectory | pkg_config
#   HEDRA_SOURCE  hedra's source tree;  HEDRA_BINARY  the build tree under test
#   WORK          scratch directory of this step;  PREFIX  install prefix
#   CONFIG        build configuration;  GENERATOR, MAKE_PROGRAM, CXX_COMPILER,
#   CXX_FLAGS, LINKER_FLAGS  forwarded so the consumer builds like hedra did
# install: cmake --install the build tree into PREFIX (emptied first).
# find_package / subdirectory: configure the consumer in WORK (emptied
# first), build it and run it (target run_consumer); find_package also checks
# that hedra came from PREFIX and nowhere else. pkg_config: compile and link
# main.cpp in one command with `pkg-config --cflags --libs hedra` of PREFIX's
# hedra.pc alone (PKG_CONFIG_LIBDIR: no system .pc files but Eigen's), as an
# embedder without CMake would, then run it.
cmake_minimum_required(VERSION 3.25)

function(run_step description)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${description} failed (${result})")
  endif()
endfunction()

if(STEP STREQUAL "install")
  file(REMOVE_RECURSE "${PREFIX}")
  set(config_args)
  if(CONFIG)
    set(config_args --config "${CONFIG}")
  endif()
  run_step("installing ${HEDRA_BINARY} into ${PREFIX}"
           "${CMAKE_COMMAND}" --install "${HEDRA_BINARY}" --prefix "${PREFIX}" ${config_args})
  file(GLOB_RECURSE config_files "${PREFIX}/*/hedraConfig.cmake")
  if(NOT config_files)
    message(FATAL_ERROR "no hedraConfig.cmake under ${PREFIX}")
  endif()
  return()
endif()

if(STEP STREQUAL "pkg_config")
  file(GLOB_RECURSE pc_files "${PREFIX}/*/hedra.pc")
  if(NOT pc_files)
    message(FATAL_ERROR "no hedra.pc under ${PREFIX}")
  endif()
  list(GET pc_files 0 pc_file)
  get_filename_component(pc_dir "${pc_file}" DIRECTORY)
  find_program(PKG_CONFIG pkg-config REQUIRED)
  # hedra's own directory first, then the system's (for eigen3.pc only).
  set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
  execute_process(COMMAND "${PKG_CONFIG}" --cflags --libs hedra RESULT_VARIABLE result OUTPUT_VARIABLE flags
                  ERROR_VARIABLE errors OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "pkg-config --cflags --libs hedra failed: ${errors}")
  endif()
  message(STATUS "pkg-config --cflags --libs hedra: ${flags}")
  string(FIND "${flags}" "-lhedra_collision -lhedra_hull" order)
  if(order EQUAL -1)
    message(FATAL_ERROR "hedra.pc does not link hedra_collision before hedra_hull: ${flags}")
  endif()
  separate_arguments(flag_list UNIX_COMMAND "${flags}")
  separate_arguments(cxx_flag_list UNIX_COMMAND "${CXX_FLAGS} ${LINKER_FLAGS}")
  file(REMOVE_RECURSE "${WORK}")
  file(MAKE_DIRECTORY "${WORK}")
  run_step("compiling the consumer with pkg-config's flags"
           "${CXX_COMPILER}" -std=c++17 -O1 ${cxx_flag_list} "${HEDRA_SOURCE}/tests/downstream/main.cpp"
           ${flag_list} -o "${WORK}/hedra_consumer")
  run_step("running the consumer (pkg_config)" "${WORK}/hedra_consumer")
  return()
endif()

set(configure_args -S "${HEDRA_SOURCE}/tests/downstream" -B "${WORK}" -G "${GENERATOR}"
    "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
if(MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM}")
endif()
if(CONFIG)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONFIG}")
endif()
if(STEP STREQUAL "find_package")
  # Only the fresh install may satisfy find_package: no registry, no system paths.
  list(APPEND configure_args -DHEDRA_CONSUMER_MODE=package "-DCMAKE_PREFIX_PATH=${PREFIX}"
       -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
elseif(STEP STREQUAL "subdirectory")
  list(APPEND configure_args -DHEDRA_CONSUMER_MODE=subdirectory "-DHEDRA_SOURCE_DIR=${HEDRA_SOURCE}"
       -DHEDRA_BUILD_TESTS=OFF -DHEDRA_BUILD_TOOLS=OFF -DHEDRA_BUILD_BENCHMARKS=OFF -DHEDRA_INSTALL=OFF)
else()
  message(FATAL_ERROR "unknown STEP '${STEP}'")
endif()

file(REMOVE_RECURSE "${WORK}")
run_step("configuring the consumer (${STEP})" "${CMAKE_COMMAND}" ${configure_args})

if(STEP STREQUAL "find_package")
  file(STRINGS "${WORK}/CMakeCache.txt" hedra_dir REGEX "^hedra_DIR:")
  string(REGEX REPLACE "^hedra_DIR:[A-Z]+=" "" hedra_dir "${hedra_dir}")
  file(REAL_PATH "${PREFIX}" real_prefix)
  file(REAL_PATH "${hedra_dir}" real_hedra_dir)
  string(FIND "${real_hedra_dir}" "${real_prefix}/" position)
  if(NOT position EQUAL 0)
    message(FATAL_ERROR "hedra was found in '${hedra_dir}', not in the fresh install ${PREFIX}")
  endif()
endif()

set(build_args --build "${WORK}" --target run_consumer --parallel 1)
if(CONFIG)
  list(APPEND build_args --config "${CONFIG}")
endif()
run_step("building and running the consumer (${STEP})" "${CMAKE_COMMAND}" ${build_args})
