# 64-bit ARM boards (Raspberry Pi 4/5 and the like). NEON is mandatory on AArch64.
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(HOULE_CROSS_TRIPLE aarch64-linux-gnu)
set(HOULE_CROSS_QEMU /usr/bin/qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/gcc-linux-cross.cmake)
