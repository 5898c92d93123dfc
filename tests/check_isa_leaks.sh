#!/usr/bin/env bash
# Fails if a function of <binary> outside the per-ISA kernels contains AVX/AVX-512 (VEX/EVEX)
# instructions: the sign of an inline function from an ISA object winning the link over the baseline
# copy, which crashes older CPUs (cmake/HouleIsa.cmake, houle_add_isa_library).
set -euo pipefail
objdump -d --no-show-raw-insn -C "$1" | awk '
  /^[0-9a-f]+ <.*>:$/ { fn = $0; next }
  # Per-ISA code is named after its xsimd arch or Isa value; PLT stubs are not code of ours.
  fn ~ /avx|fma3|sse4_2|\(houle::Isa\)[123]|@plt/ { next }
  $2 ~ /^v[a-z0-9]+$/ && ($0 ~ /%[xyz]mm/) { bad[fn] = $2 }
  END {
    n = 0
    for (f in bad) { print "baseline code uses " bad[f] ": " f; n++ }
    if (n) exit 1
    print "no AVX instructions outside the per-ISA kernels"
  }'
