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

# ROS 1 bags (optional, like MPI): with Debian's librosbag-storage-dev, `gyrosid import --format rosbag` reads
# sensor_msgs/Imu. Found by hand: the package's CMake config loads ament's Python tooling through pluginlib,
# and its pkg-config file requires a pluginlib.pc that Debian does not ship. Its bag.h includes the ROS 2
# pluginlib, class_loader, rcutils, rcpputils and ament_index_cpp headers, each in a folder of its own.
find_path(ROSBAG_INCLUDE_DIR rosbag/bag.h)
set(GYROSID_ROSBAG_INCLUDE_DIRS)
if(NOT ROSBAG_INCLUDE_DIR)
  list(APPEND GYROSID_ROSBAG_INCLUDE_DIRS ${ROSBAG_INCLUDE_DIR})
elseif(NOT ROSBAG_INCLUDE_DIR STREQUAL "/usr/include")  # the compiler's own: naming it breaks #include_next
  list(APPEND GYROSID_ROSBAG_INCLUDE_DIRS ${ROSBAG_INCLUDE_DIR})
endif()
foreach(header pluginlib/class_loader.hpp class_loader/class_loader.hpp rcutils/types.h rcpputils/filesystem_helper.hpp
               ament_index_cpp/get_resource.hpp)
  string(REGEX REPLACE "/.*" "" folder ${header})
  find_path(GYROSID_ROS_${folder}_DIR ${header} PATH_SUFFIXES ${folder})
  list(APPEND GYROSID_ROSBAG_INCLUDE_DIRS ${GYROSID_ROS_${folder}_DIR})
endforeach()
set(GYROSID_ROSBAG_LIBRARIES)
foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge)
  find_library(GYROSID_ROS_${lib}_LIBRARY ${lib})
  list(APPEND GYROSID_ROSBAG_LIBRARIES ${GYROSID_ROS_${lib}_LIBRARY})
endforeach()
if(NOT "${GYROSID_ROSBAG_INCLUDE_DIRS};${GYROSID_ROSBAG_LIBRARIES}" MATCHES "NOTFOUND")
  # Used per source file (CMakeLists.txt), not as a target, so no other object's command line changes; -isystem
  # keeps the ROS headers' own warnings out.
  set(GYROSID_HAVE_ROSBAG ON)
  set(GYROSID_ROSBAG_COMPILE_OPTIONS)
  foreach(dir ${GYROSID_ROSBAG_INCLUDE_DIRS})
    list(APPEND GYROSID_ROSBAG_COMPILE_OPTIONS -isystem ${dir})
  endforeach()
else()
  set(GYROSID_HAVE_ROSBAG OFF)
  message(STATUS "gyrosid: ROS 1 bag library not found - `import --format rosbag` is not built (Debian: librosbag-storage-dev)")
endif()
