# Decides UNISPH_HAS_MPI from UNISPH_ENABLE_MPI (AUTO|ON|OFF) and whether MPI is found, and
# UNISPH_HAS_NCCL: where the CUDA backend is built and nccl.h and libnccl.so.2 are found, the
# communication layer compiles its NCCL transport (src/comm/nccl_transport.cpp).
set(UNISPH_HAS_MPI OFF)
if(NOT UNISPH_ENABLE_MPI STREQUAL "OFF")
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    set(UNISPH_HAS_MPI ON)
  elseif(UNISPH_ENABLE_MPI STREQUAL "ON")
    message(FATAL_ERROR "UNISPH_ENABLE_MPI=ON but no MPI for C++ was found: install libopenmpi-dev "
                        "(scripts/setup.sh), set MPI_HOME, or configure with -DUNISPH_ENABLE_MPI=OFF")
  else()
    message(STATUS "unisph: MPI not found, building the communication layer's serial fallback only")
  endif()
endif()

set(UNISPH_HAS_NCCL OFF)
if(UNISPH_HAS_MPI AND UNISPH_HAS_CUDA)
  find_path(UNISPH_NCCL_INCLUDE_DIR nccl.h HINTS ${CUDAToolkit_INCLUDE_DIRS} ENV NCCL_HOME PATH_SUFFIXES include)
  find_library(UNISPH_NCCL_LIBRARY NAMES libnccl.so.2 nccl HINTS ${CUDAToolkit_LIBRARY_DIR} ENV NCCL_HOME
               PATH_SUFFIXES lib lib64)
  if(UNISPH_NCCL_INCLUDE_DIR AND UNISPH_NCCL_LIBRARY)
    set(UNISPH_HAS_NCCL ON)
  else()
    message(STATUS "unisph: nccl.h or libnccl.so.2 not found, no NCCL transport (host-staged only)")
  endif()
endif()
