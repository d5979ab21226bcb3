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
# Open CASCADE 7.6 (libocct-data-exchange-dev, libocct-modeling-algorithms-dev, …): STEP/IGES parts,
# private to ingest/io/cad_occt.cpp. ON when found; OFF builds read meshes only (CAD files: a clear error).
find_package(OpenCASCADE QUIET CONFIG)  # 7.6 on Debian 12 (its config accepts no version request)
option(MILLNET_CAD "Read STEP/IGES parts through Open CASCADE" ${OpenCASCADE_FOUND})
if(MILLNET_CAD AND NOT OpenCASCADE_FOUND)
  message(FATAL_ERROR "MILLNET_CAD=ON but Open CASCADE was not found (apt-get install libocct-data-exchange-dev "
                      "libocct-modeling-algorithms-dev libocct-modeling-data-dev libocct-foundation-dev)")
endif()
message(STATUS "millnet: CAD (STEP/IGES through Open CASCADE ${OpenCASCADE_VERSION}): ${MILLNET_CAD}")
# The Open CASCADE toolkits the reader links (the tests add TKPrim and TKBO to build parts).
set(MILLNET_OCCT_LIBS TKSTEP TKSTEPBase TKIGES TKXSBase TKMesh TKTopAlgo TKBRep TKG3d TKMath TKernel)
