# Finds every dependency gyrosid uses. Each comes from a Debian 12 package that scripts/setup.sh installs;
# a missing one stops the configure step with the name of the package to install.

find_package(PkgConfig QUIET)
find_package(Threads REQUIRED)

function(gyrosid_missing what debian_package)
  message(FATAL_ERROR
    "gyrosid: ${what} not found. Install the Debian package '${debian_package}' "
    "(scripts/setup.sh installs every dependency: scripts/setup.sh build).")
endfunction()

if(NOT PkgConfig_FOUND)
  gyrosid_missing("pkg-config" "pkg-config")
endif()

find_package(Eigen3 3.4 QUIET CONFIG)
if(NOT Eigen3_FOUND)
  gyrosid_missing("Eigen 3.4" "libeigen3-dev")
endif()

find_package(Ceres 2.1 QUIET CONFIG)
if(NOT Ceres_FOUND)
  gyrosid_missing("Ceres Solver" "libceres-dev")
endif()

pkg_check_modules(NLOPT QUIET IMPORTED_TARGET nlopt_cxx)
if(NOT NLOPT_FOUND)
  gyrosid_missing("NLopt (C++ interface)" "libnlopt-cxx-dev")
endif()

pkg_check_modules(IPOPT QUIET IMPORTED_TARGET ipopt)
if(NOT IPOPT_FOUND)
  gyrosid_missing("Ipopt" "coinor-libipopt-dev")
endif()

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
if(NOT CHOLMOD_INCLUDE_DIR OR NOT CHOLMOD_LIBRARY)
  gyrosid_missing("SuiteSparse CHOLMOD" "libsuitesparse-dev")
endif()
add_library(gyrosid::cholmod INTERFACE IMPORTED)
target_include_directories(gyrosid::cholmod INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(gyrosid::cholmod INTERFACE ${CHOLMOD_LIBRARY})

find_package(yaml-cpp QUIET CONFIG)
if(NOT yaml-cpp_FOUND)
  gyrosid_missing("yaml-cpp" "libyaml-cpp-dev")
endif()

find_package(nlohmann_json 3.10 QUIET CONFIG)
if(NOT nlohmann_json_FOUND)
  gyrosid_missing("nlohmann-json" "nlohmann-json3-dev")
endif()

find_package(CLI11 2.1 QUIET CONFIG)
if(NOT CLI11_FOUND)
  gyrosid_missing("CLI11" "libcli11-dev")
endif()

# MPI is optional: with it, the gyrosid-mpi executable spreads Monte Carlo runs over processes.
find_package(MPI QUIET COMPONENTS CXX)
if(NOT MPI_CXX_FOUND)
  message(STATUS "gyrosid: MPI not found - gyrosid-mpi is not built (Debian: libopenmpi-dev openmpi-bin)")
endif()

# Python bindings (python/): pybind11 and the Debian interpreter, whose numpy the tests use (a pyenv or venv
# python earlier on PATH may lack it).
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
set(PYBIND11_FINDPYTHON ON)
find_package(Python3 QUIET COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG QUIET)
if(NOT pybind11_FOUND OR NOT Python3_FOUND)
  gyrosid_missing("pybind11 and the Python headers (the Python bindings)" "pybind11-dev python3-dev")
endif()

find_program(GNUPLOT_EXECUTABLE gnuplot)
if(NOT GNUPLOT_EXECUTABLE)
  gyrosid_missing("gnuplot (plots are rendered with it)" "gnuplot-nox")
endif()

if(GYROSID_BUILD_TESTS)
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    gyrosid_missing("GoogleTest" "libgtest-dev")
  endif()
  if(NOT TARGET GTest::gmock)
    gyrosid_missing("GoogleMock" "libgmock-dev")
  endif()
endif()

if(GYROSID_BUILD_BENCHMARKS)
  find_package(benchmark QUIET CONFIG)
  if(NOT benchmark_FOUND)
    gyrosid_missing("Google Benchmark" "libbenchmark-dev")
  endif()
endif()
