# Every dependency comes from a Debian 12 package (scripts/setup.sh installs them); nothing is
# downloaded at configure or build time.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)          # libeigen3-dev
find_package(OpenMP REQUIRED)                        # g++
find_package(nlohmann_json 3.11 REQUIRED)            # nlohmann-json3-dev
find_package(assimp REQUIRED)                        # libassimp-dev (only in ingest/src/load_mesh_assimp.cpp)
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs)  # libopencv-dev
find_package(CLI11 REQUIRED)                         # libcli11-dev
find_package(nanoflann REQUIRED)                     # libnanoflann-dev
# Clipper 6 (libpolyclipping-dev) ships a pkg-config file, not a CMake package.
find_package(PkgConfig REQUIRED)
pkg_check_modules(POLYCLIPPING REQUIRED IMPORTED_TARGET polyclipping)
# Open MPI (libopenmpi-dev, openmpi-bin): `mpirun -np K millnet dataset|predict|finish` (issue 10).
# Only app/mpi_cluster.cpp includes mpi.h; without MPI the same code runs as one rank.
if(MILLNET_MPI)
  enable_language(C)  # FindMPI's C component probes with the C compiler
  find_package(MPI COMPONENTS C)
  if(NOT MPI_C_FOUND)
    message(STATUS "millnet: MPI not found; building the one-rank implementation (MILLNET_MPI OFF)")
    set(MILLNET_MPI OFF)  # for this configure only: found once installed
  endif()
endif()
if(MILLNET_TESTS)
  find_package(GTest REQUIRED)                       # libgtest-dev
endif()
if(MILLNET_BENCH)
  find_package(benchmark REQUIRED)                   # libbenchmark-dev
endif()
