# Cross-compiling for 64-bit ARM (Raspberry Pi 4/5, Jetson) on Debian with
# crossbuild-essential-arm64 and the :arm64 multiarch -dev packages:
#   cmake -S . -B build-arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64.cmake
# See scripts/test.d/60-arm64.sh for the packages and docs/deploy.md.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Multiarch: arm64 libraries and CMake packages live in /usr/lib/aarch64-linux-gnu,
# architecture-independent headers in /usr/include. Host programs are used as they are.
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu /usr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

# pkg-config (libsystemd) must read the arm64 .pc files, never the host's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/aarch64-linux-gnu/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")

# Run target programs (tests) under qemu-user.
find_program(WHEELTEC_QEMU_AARCH64 qemu-aarch64)
if(WHEELTEC_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${WHEELTEC_QEMU_AARCH64} -L /usr/aarch64-linux-gnu)
endif()
