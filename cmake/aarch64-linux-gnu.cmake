# CMake toolchain file: 64-bit ARM Linux with Debian's cross compilers
# (crossbuild-essential-arm64), tests run under qemu's user-mode emulator.
# Used by `make test-arm` (docs/install.md, "Embedded build"):
#   cmake -S . -B build-arm64 --toolchain cmake/aarch64-linux-gnu.cmake \
#     -DSTRIDEMAP_CORE_LAYERS_ONLY=ON -DSTRIDEMAP_GTEST_SOURCE_DIR=/usr/src/googletest
#
# No sysroot: Debian's cross toolchain keeps the target's C and C++ runtime
# in /usr/aarch64-linux-gnu and finds it itself. The only package the
# core layers look for, Eigen, is headers and a CMake package under
# /usr/share, the same for every architecture, so the host's copy serves.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

# Libraries and headers of the target only (never the host's x86-64 ones);
# packages from the host's /usr too, for the architecture-independent ones.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

# ctest and gtest_discover_tests run every test program through this: -L
# points the emulator's dynamic loader at the target's runtime libraries.
find_program(STRIDEMAP_QEMU_AARCH64 qemu-aarch64)
if(STRIDEMAP_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${STRIDEMAP_QEMU_AARCH64} -L /usr/aarch64-linux-gnu)
endif()
