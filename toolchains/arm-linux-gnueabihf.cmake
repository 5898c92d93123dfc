# 32-bit ARMv7 hard-float boards. The baseline is Debian armhf's (VFPv3-D16, no NEON) so the binary
# runs on any armhf board; the NEON kernels are compiled with -mfpu=neon-vfpv4 (cmake/HouleIsa.cmake)
# and chosen at start-up when the CPU has NEON.
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(HOULE_CROSS_TRIPLE arm-linux-gnueabihf)
set(HOULE_CROSS_QEMU /usr/bin/qemu-arm)
set(CMAKE_CXX_FLAGS_INIT "-march=armv7-a -mfpu=vfpv3-d16 -mfloat-abi=hard")
include(${CMAKE_CURRENT_LIST_DIR}/gcc-linux-cross.cmake)
