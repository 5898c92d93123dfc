#!/usr/bin/env bash
# Golden images: the frames of tests/golden/golden_set.sh, rendered on every instruction set this CPU
# runs (but those in $HOULE_GOLDEN_SKIP_ISAS), against the committed PNGs (scripts/regen-goldens writes them, never this test), compared with
# OpenImageIO's idiff. Usage: test_golden.sh <source dir> <houle command...> (an emulator may lead).
#
# Tolerance, per golden (the three frames of a scene together), in 8-bit sRGB units (1 LSB = 1/255 = 0.0039):
#   * a pixel fails when a channel differs by more than 1.5 LSB (a 1-LSB rounding flip passes);
#   * at most 0.1 % of the pixels may fail (27 of the 27648 in 3 x 128x72: sub-pixel slivers resolved
#     differently), and none by more than 0.1 (25 LSB);
#   * the RMS difference over all channels stays under 0.3 LSB (0.0012): a shift of the whole image by
#     one LSB, i.e. about 1 % in brightness at mid grey, fails.
# Why this is enough and not too much: tests/golden/README.md.
set -uo pipefail
src=$1; shift
houle=("$@")
. "$src/tests/golden/golden_set.sh"
fail_lsb=0.0059 fail_percent=0.1 hard_fail=0.1 rms_max=0.0012
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
pass=0 fail=0

# compare <golden.png> <frame.ppm> <label>: idiff's verdict on the per-pixel bounds, then the RMS bound.
compare() {
  local out rc rms
  out=$(idiff -v -fail "$fail_lsb" -failpercent "$fail_percent" -hardfail "$hard_fail" "$1" "$2" 2>&1); rc=$?
  rms=$(sed -nE 's/^ *RMS error = ([0-9.eE+-]+).*/\1/p' <<<"$out")
  # idiff exits 0 (pass), 1 (differences under the failure bounds: its "warning") or 2 (failure).
  if [ "$rc" -le 1 ] && [ -n "$rms" ] && awk -v r="$rms" -v m="$rms_max" 'BEGIN { exit !(r <= m) }'; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    printf 'FAIL %s (idiff exit %s, RMS %s, bound %s):\n%s\n' "$3" "$rc" "${rms:-?}" "$rms_max" "$out"
  fi
}

# The ISAs compiled in, from "houle 0.1.0 (ISA avx2; compiled: scalar sse4.2 avx2 avx512)".
version=$("${houle[@]}" --version 2>&1)
isas=$(sed -nE 's/.*compiled: ([^)]*)\).*/\1/p' <<<"$version")
[ -n "$isas" ] || { printf 'FAIL: no compiled ISAs in houle --version, which said:\n%s\n' "$version"; exit 1; }
ran=()
for isa in $isas; do
  if [[ " ${HOULE_GOLDEN_SKIP_ISAS:-} " == *" $isa "* ]]; then
    echo "golden: $isa skipped on this target (HOULE_GOLDEN_SKIP_ISAS)"
    continue
  fi
  if ! HOULE_ISA=$isa "${houle[@]}" --version >/dev/null 2>&1; then
    echo "golden: $isa is compiled in but this CPU cannot run it"
    continue
  fi
  ran+=("$isa")
  for name in "${golden_scenes[@]}"; do
    if ! HOULE_ISA=$isa golden_render "$src" "$name" "$work/$name.rgb" "${houle[@]}"; then
      fail=$((fail + 1)); echo "FAIL $name on $isa: houle render failed"; continue
    fi
    golden_strip_ppm "$work/$name.rgb" "$work/$name.ppm"
    compare "$src/tests/golden/$name.png" "$work/$name.ppm" "$name on $isa"
  done
done
echo "golden: ISAs ${ran[*]}; ${pass} comparisons (scene x ISA) passed, ${fail} failed"
[ "${#ran[@]}" -gt 0 ] && [ "$fail" -eq 0 ]
