# Every dependency comes from Debian's packages (scripts/install-deps).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(Ceres 2.1 REQUIRED)
find_package(tomlplusplus 3 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 2 REQUIRED)
find_package(fmt REQUIRED)
find_package(GTest REQUIRED)
find_package(benchmark REQUIRED)
find_package(OpenMP REQUIRED)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)  # compressed VTU arrays
# OpenMPI (issue 15): `mpirun -np N tricot identify` spreads the tests over ranks. On by default.
if(TRICOT_MPI)
  find_package(MPI COMPONENTS CXX)
  if(NOT MPI_CXX_FOUND)
    message(FATAL_ERROR "TRICOT_MPI is ON but no MPI was found (OpenMPI: Debian's libopenmpi-dev and "
                        "openmpi-bin). Run scripts/install-deps, or configure with -DTRICOT_MPI=OFF to build "
                        "without MPI (identifications then run in one process).")
  endif()
endif()

# SuiteSparse (CHOLMOD, UMFPACK) through Eigen's support modules. Debian's package ships no CMake
# config for these, so find the libraries directly.
find_path(SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
set(_ss_targets)
foreach(lib cholmod umfpack amd colamd camd ccolamd suitesparseconfig)
  find_library(SUITESPARSE_${lib}_LIBRARY ${lib} REQUIRED)
  list(APPEND _ss_targets ${SUITESPARSE_${lib}_LIBRARY})
endforeach()
add_library(tricot_suitesparse INTERFACE)
target_include_directories(tricot_suitesparse SYSTEM INTERFACE ${SUITESPARSE_INCLUDE_DIR})
target_link_libraries(tricot_suitesparse INTERFACE ${_ss_targets})

# OpenCV: Debian's split -dev packages (core, imgproc, imgcodecs) ship no CMake config; find them directly.
find_path(OPENCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
add_library(tricot_opencv INTERFACE)
target_include_directories(tricot_opencv SYSTEM INTERFACE ${OPENCV_INCLUDE_DIR})
foreach(lib opencv_imgcodecs opencv_imgproc opencv_core)
  find_library(OPENCV_${lib}_LIBRARY ${lib} REQUIRED)
  target_link_libraries(tricot_opencv INTERFACE ${OPENCV_${lib}_LIBRARY})
endforeach()

find_program(GNUPLOT_EXECUTABLE gnuplot)
find_program(DEBIAN_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)

# Gmsh (Debian's libgmsh-dev, issue 28): fem reads .msh files and meshes .geo geometries through its
# C++ API; no CMake config is shipped, so find the header and library directly.
find_path(GMSH_INCLUDE_DIR gmsh.h REQUIRED)
find_library(GMSH_LIBRARY gmsh REQUIRED)
add_library(tricot_gmsh INTERFACE)
target_include_directories(tricot_gmsh SYSTEM INTERFACE ${GMSH_INCLUDE_DIR})
target_link_libraries(tricot_gmsh INTERFACE ${GMSH_LIBRARY})
