# Shared part of the Debian cross toolchains: the target's sysroot holds libc and libstdc++ only;
# header-only GLM and xsimd come from the host (cmake/HouleDependencies.cmake) and GoogleTest is
# built from Debian's /usr/src/googletest. Tests run under qemu-user through the emulator below.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${HOULE_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${HOULE_CROSS_TRIPLE}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${HOULE_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH /usr/${HOULE_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_CROSSCOMPILING_EMULATOR ${HOULE_CROSS_QEMU} -L /usr/${HOULE_CROSS_TRIPLE})
